#include "belief/speed_choice.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "sim/fast_putt.hpp"

namespace mg::belief {
namespace {

constexpr double kPi = 3.14159265358979323846;

void require(bool ok, const char* key, const char* expected, double got) {
  if (!ok)
    throw InputError(fmt::format("speed choice: {}: expected {}, got {}", key, expected, got));
}

/// Gaussian weights exp(-x^2 / 2) at x = k step / sigma for k in -n..n.
std::vector<double> gaussian_weights(int n, double step, double sigma) {
  std::vector<double> w;
  for (int k = -n; k <= n; ++k) {
    const double x = k * step / sigma;
    w.push_back(std::exp(-0.5 * x * x));
  }
  return w;
}

}  // namespace

void SpeedChoiceOptions::validate() const {
  require(speed_steps >= 0 && speed_steps <= 100, "speed_steps", "0..100", speed_steps);
  require(std::isfinite(speed_step) && speed_step > 0.0 && speed_step * speed_steps < 1.0,
          "speed_step", "> 0 with speed_step * speed_steps < 1", speed_step);
  require(angle_cells >= 0 && angle_cells <= 100, "angle_cells", "0..100", angle_cells);
  require(std::isfinite(angle_step) && angle_step > 0.0 && angle_step < 0.1, "angle_step",
          "0..0.1 rad", angle_step);
  require(std::isfinite(angle_sigma) && angle_sigma > 0.0, "angle_sigma", "> 0 rad", angle_sigma);
  require(std::isfinite(speed_sigma) && speed_sigma > 0.0, "speed_sigma", "> 0", speed_sigma);
  require(std::isfinite(launch_per_club) && launch_per_club > 0.0 && launch_per_club < 10.0,
          "launch_per_club", "0..10", launch_per_club);
  require(std::isfinite(launch_angle_bias) && std::abs(launch_angle_bias) < 0.5,
          "launch_angle_bias", "|bias| < 0.5 rad", launch_angle_bias);
  require(std::isfinite(speed_min) && speed_min >= 0.0, "speed_min", ">= 0 m/s", speed_min);
  require(std::isfinite(speed_max) && speed_max > speed_min, "speed_max", "> speed_min", speed_max);
}

SpeedChoice choose_club_speed(const sim::World& world, std::array<double, 2> ball,
                              std::array<double, 2> hole, double angle, double equivalent_speed,
                              const SpeedChoiceOptions& options) {
  options.validate();
  require(std::isfinite(angle), "angle", "finite", angle);
  require(std::isfinite(equivalent_speed) && equivalent_speed > 0.0, "equivalent_speed", "> 0",
          equivalent_speed);
  const int ns = options.speed_steps, na = options.angle_cells;
  const int speeds = 2 * ns + 1, angles = 2 * na + 1;
  SpeedChoice best;
  best.club_speed = std::clamp(equivalent_speed, options.speed_min, options.speed_max);
  // sunk[k][i]: the hit at speed k, angle i sinks in the believed world.
  std::vector<std::vector<char>> sunk(static_cast<std::size_t>(speeds),
                                      std::vector<char>(static_cast<std::size_t>(angles), 0));
  std::vector<char> allowed(static_cast<std::size_t>(speeds), 0);
  const sim::DataPtr d = world.make_data();
  bool any = false;
  for (int k = 0; k < speeds; ++k) {
    const double club = equivalent_speed * (1.0 + (k - ns) * options.speed_step);
    allowed[static_cast<std::size_t>(k)] = club >= options.speed_min && club <= options.speed_max;
    for (int i = 0; i < angles; ++i) {
      sim::PuttRequest r;
      // Wrapped: a hit along -x turns past +-pi (a request's range is one turn).
      r.angle = std::remainder(angle + options.launch_angle_bias + (i - na) * options.angle_step,
                               2.0 * kPi);
      r.speed = options.launch_per_club * club;
      r.start = ball;
      const sim::PuttOutcome p = sim::fast_putt(world, d.get(), hole, r);
      ++best.imagined_putts;
      sunk[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] = p.sunk ? 1 : 0;
      any = any || p.sunk;
    }
  }
  if (!any) return best;
  const auto wa = gaussian_weights(na, options.angle_step, options.angle_sigma);
  const auto wv = gaussian_weights(ns, options.speed_step, options.speed_sigma);
  // Normalised over the whole Gaussians: cells off the grid count as misses.
  double wa_sum = 0.0, wv_sum = 0.0;
  for (int i = -4 * na; i <= 4 * na; ++i)
    wa_sum += std::exp(-0.5 * std::pow(i * options.angle_step / options.angle_sigma, 2));
  for (int j = -4 * ns; j <= 4 * ns; ++j)
    wv_sum += std::exp(-0.5 * std::pow(j * options.speed_step / options.speed_sigma, 2));
  int chosen = -1;
  double chosen_score = -1.0;
  for (int k = 0; k < speeds; ++k) {
    if (!allowed[static_cast<std::size_t>(k)]) continue;
    double s = 0.0;
    for (int j = 0; j < speeds; ++j) {
      const int dj = j - k;
      if (dj < -ns || dj > ns) continue;
      double row = 0.0;
      for (int i = 0; i < angles; ++i)
        row += wa[static_cast<std::size_t>(i)] *
               sunk[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)];
      s += wv[static_cast<std::size_t>(dj + ns)] * row;
    }
    s /= wa_sum * wv_sum;
    // Ties (to rounding) go to the speed nearest the equivalent one.
    const bool nearer = chosen < 0 || std::abs(k - ns) < std::abs(chosen - ns);
    if (s > chosen_score + 1e-12 || (s > chosen_score - 1e-12 && nearer)) {
      chosen = k;
      chosen_score = s;
    }
  }
  if (chosen < 0 || chosen_score <= 0.0) return best;
  best.club_speed = equivalent_speed * (1.0 + (chosen - ns) * options.speed_step);
  best.score = chosen_score;
  return best;
}

}  // namespace mg::belief
