#include "belief/arm_fit.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::belief {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

std::array<double, 2> robust_mean(std::vector<double> values) {
  const std::size_t n = values.size();
  if (n == 0) return {0.0, kInf};
  if (n == 1) return {values[0], kInf};
  const double med = median(values);
  std::vector<double> dev(n);
  for (std::size_t i = 0; i < n; ++i) dev[i] = std::abs(values[i] - med);
  double scale = 1.4826 * median(dev);
  if (!(scale > 0.0)) {  // half or more agree exactly: the spread of the rest, or none
    double sum = 0.0;
    for (double d : dev) sum += d * d;
    scale = std::sqrt(sum / static_cast<double>(n - 1));
  }
  if (!(scale > 0.0)) return {med, 0.0};
  // Huber's M-estimate by iteratively reweighted means.
  constexpr double kHuber = 1.345;
  const double clip = kHuber * scale;
  double mu = med;
  for (int it = 0; it < 100; ++it) {
    double sw = 0.0, swx = 0.0;
    for (double v : values) {
      const double r = std::abs(v - mu);
      const double w = r <= clip ? 1.0 : clip / r;
      sw += w;
      swx += w * v;
    }
    const double next = swx / sw;
    const bool done = std::abs(next - mu) <= 1e-12 * scale;
    mu = next;
    if (done) break;
  }
  // Its asymptotic variance, E[psi^2] / E[psi']^2 / n, from the sample.
  double psi2 = 0.0;
  int inside = 0;
  for (double v : values) {
    const double r = v - mu;
    const double psi = std::clamp(r, -clip, clip);
    psi2 += psi * psi;
    inside += std::abs(r) <= clip;
  }
  const double dn = static_cast<double>(n);
  const double slope = std::max(1, inside) / dn;
  return {mu, std::sqrt(psi2 / (dn - 1.0) / dn) / slope};
}

ArmEstimate fit_arm(const std::vector<ArmObservation>& observations) {
  std::vector<double> scales, biases;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const ArmObservation& o = observations[i];
    if (!std::isfinite(o.commanded_speed) || o.commanded_speed < 0.0)
      throw InputError(fmt::format(
          "fit_arm: observations[{}].commanded_speed: expected a finite speed >= 0 m/s, got {}", i,
          o.commanded_speed));
    const double predicted = o.predicted_speed > 0.0 ? o.predicted_speed : o.commanded_speed;
    if (std::isfinite(o.reached_speed) && o.reached_speed > 0.0 && std::isfinite(predicted) &&
        predicted > 0.0)
      scales.push_back(o.reached_speed / predicted);
    if (std::isfinite(o.observed_launch_angle) && std::isfinite(o.predicted_launch_angle))
      biases.push_back(
          std::remainder(o.observed_launch_angle - o.predicted_launch_angle, 2.0 * kPi));
  }
  ArmEstimate e;
  e.speed_observations = static_cast<int>(scales.size());
  e.angle_observations = static_cast<int>(biases.size());
  if (!scales.empty()) {
    const auto m = robust_mean(scales);
    e.club_speed_scale = m[0];
    e.club_speed_scale_std = m[1];
  }
  if (!biases.empty()) {
    const auto m = robust_mean(biases);
    e.launch_angle_bias = m[0];
    e.launch_angle_bias_std = m[1];
  }
  return e;
}

double path_direction(const std::vector<std::array<double, 3>>& samples, double t_from,
                      double t_to) {
  double sx = 0.0, sy = 0.0;
  int n = 0;
  const std::array<double, 3>* first = nullptr;
  const std::array<double, 3>* last = nullptr;
  for (const auto& s : samples) {
    if (!(s[0] >= t_from && s[0] <= t_to)) continue;
    if (!first) first = &s;
    last = &s;
    sx += s[1];
    sy += s[2];
    ++n;
  }
  if (n < 3) return std::numeric_limits<double>::quiet_NaN();
  const double mx = sx / n, my = sy / n;
  double cxx = 0.0, cxy = 0.0, cyy = 0.0;
  for (const auto& s : samples) {
    if (!(s[0] >= t_from && s[0] <= t_to)) continue;
    const double dx = s[1] - mx, dy = s[2] - my;
    cxx += dx * dx;
    cxy += dx * dy;
    cyy += dy * dy;
  }
  if (!(cxx + cyy > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  // The principal axis of the scatter; its sign from the way the ball went.
  const double angle = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
  double ux = std::cos(angle), uy = std::sin(angle);
  if (ux * ((*last)[1] - (*first)[1]) + uy * ((*last)[2] - (*first)[2]) < 0.0) {
    ux = -ux;
    uy = -uy;
  }
  return std::atan2(uy, ux);
}

}  // namespace mg::belief
