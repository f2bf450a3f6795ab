#include "ds/demonstrations.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "core/io.hpp"

namespace mg::ds {
namespace {

using Vec3 = Eigen::Vector3d;

Vec3 bezier(const std::array<Vec3, 6>& p, double u) {
  static constexpr std::array<double, 6> kBinom{1, 5, 10, 10, 5, 1};
  Vec3 r = Vec3::Zero();
  for (int i = 0; i < 6; ++i) r += kBinom[i] * std::pow(u, i) * std::pow(1.0 - u, 5 - i) * p[i];
  return r;
}

Vec3 bezier_derivative(const std::array<Vec3, 6>& p, double u) {
  static constexpr std::array<double, 5> kBinom{1, 4, 6, 4, 1};
  Vec3 r = Vec3::Zero();
  for (int i = 0; i < 5; ++i)
    r += 5.0 * kBinom[i] * std::pow(u, i) * std::pow(1.0 - u, 4 - i) * (p[i + 1] - p[i]);
  return r;
}

Demonstration generate_one(const DemoGeneratorConfig& c, int id, Rng& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Vec3 psi0(1.0, 0.0, 0.0);
  const double behind = c.behind_min + (c.behind_max - c.behind_min) * unit(rng);
  const double above = c.above_min + (c.above_max - c.above_min) * unit(rng);
  const double side = c.side_min + (c.side_max - c.side_min) * unit(rng);
  const Vec3 start = c.ball + Vec3(-behind, side, above);

  // Quintic Bezier: P3..P5 on the hitting line (straight, curvature-free final approach).
  std::array<Vec3, 6> p;
  p[5] = c.ball;
  p[4] = c.ball - c.straight_length * psi0;
  p[3] = c.ball - 2.0 * c.straight_length * psi0;
  const Vec3 line_entry = c.ball - 3.0 * c.straight_length * psi0;
  p[0] = start;
  p[2] = 0.5 * (start + line_entry) + Vec3(0.0, 0.02 * normal(rng), -0.25 * above);
  p[1] = start + (p[2] - start) / 3.0;

  // Arc-length table for re-parameterisation by distance travelled.
  constexpr int kTable = 4000;
  std::vector<double> arc(kTable + 1, 0.0);
  Vec3 prev = p[0];
  for (int i = 1; i <= kTable; ++i) {
    const Vec3 q = bezier(p, static_cast<double>(i) / kTable);
    arc[i] = arc[i - 1] + (q - prev).norm();
    prev = q;
  }
  const double length = arc.back();

  const double v_hit = c.hitting_speed * (1.0 + c.hitting_speed_jitter * normal(rng));
  const double tp = c.tau_peak;
  const double v_peak = v_hit / std::pow(std::sin(std::numbers::pi / (2.0 * tp)), 2);
  // Distance covered by time tau (normalised), per unit of T * v_peak.
  const auto dist = [tp](double tau) {
    return 0.5 * tau - tp / (2.0 * std::numbers::pi) * std::sin(std::numbers::pi * tau / tp);
  };
  const double duration = length / (v_peak * dist(1.0));

  Demonstration d;
  d.id = id;
  const int n_steps = static_cast<int>(std::ceil(duration / c.sample_period - 1e-9));
  for (int i = 0; i <= n_steps; ++i) {
    const double t = std::min(i * c.sample_period, duration);
    const double tau = t / duration;
    const double s = duration * v_peak * dist(tau);
    const double speed = v_peak * std::pow(std::sin(std::numbers::pi * tau / (2.0 * tp)), 2);
    // Invert the arc-length table.
    const auto it = std::lower_bound(arc.begin(), arc.end(), s);
    double u = 1.0;
    if (it != arc.end()) {
      const auto j = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - arc.begin()));
      const double f = (s - arc[j - 1]) / std::max(arc[j] - arc[j - 1], 1e-15);
      u = (static_cast<double>(j - 1) + std::clamp(f, 0.0, 1.0)) / kTable;
    }
    const Vec3 tangent = bezier_derivative(p, u).normalized();
    Vec3 x = bezier(p, u);
    Vec3 v = speed * tangent;
    for (int a = 0; a < 3; ++a) {
      x[a] += c.position_noise * normal(rng);
      v[a] += c.velocity_noise * normal(rng);
    }
    d.t.push_back(t);
    d.x.push_back(x);
    d.xdot.push_back(v);
  }
  return d;
}

}  // namespace

void DemoGeneratorConfig::validate() const {
  if (count < 1) throw InputError(fmt::format("demonstration count: expected >= 1, got {}", count));
  for (int a = 0; a < 3; ++a) require_finite("ball position", ball[a]);
  require_positive("behind_min", behind_min);
  require_in_range("behind_max", behind_max, behind_min, 10.0);
  require_non_negative("above_min", above_min);
  require_in_range("above_max", above_max, above_min, 10.0);
  require_in_range("side_max", side_max, side_min, 10.0);
  require_positive("hitting_speed", hitting_speed);
  require_in_range("hitting_speed_jitter", hitting_speed_jitter, 0.0, 0.2);
  require_in_range("tau_peak", tau_peak, 0.55, 1.0);
  require_positive("straight_length", straight_length);
  require_positive("sample_period", sample_period);
  require_non_negative("position_noise", position_noise);
  require_non_negative("velocity_noise", velocity_noise);
}

std::vector<Demonstration> generate_demonstrations(const DemoGeneratorConfig& config, Rng& rng) {
  config.validate();
  std::vector<Demonstration> demos;
  for (int i = 0; i < config.count; ++i) demos.push_back(generate_one(config, i, rng));
  return demos;
}

std::vector<Demonstration> demonstrations_from_table(const CsvTable& table,
                                                     std::size_t min_samples) {
  const std::array<const char*, 8> names{"demo", "t", "x", "y", "z", "vx", "vy", "vz"};
  std::array<std::size_t, 8> col{};
  for (std::size_t i = 0; i < names.size(); ++i) col[i] = table.column_index(names[i]);
  if (table.num_rows() == 0)
    throw InputError(
        fmt::format("{}: expected at least one demonstration sample, got none", table.source));

  std::vector<Demonstration> demos;
  std::vector<int> seen;
  for (std::size_t r = 0; r < table.num_rows(); ++r) {
    const auto& row = table.rows[r];
    const double id_value = row[col[0]];
    if (id_value != std::round(id_value) || std::abs(id_value) > 1e9)
      throw InputError(fmt::format("{}: row {}: column 'demo': expected an integer id, got {}",
                                   table.source, r + 1, id_value));
    const int id = static_cast<int>(id_value);
    if (demos.empty() || demos.back().id != id) {
      if (std::find(seen.begin(), seen.end(), id) != seen.end())
        throw InputError(fmt::format(
            "{}: row {}: demonstration {} is not contiguous (its rows must be together)",
            table.source, r + 1, id));
      seen.push_back(id);
      demos.emplace_back();
      demos.back().id = id;
    }
    Demonstration& d = demos.back();
    // Positions [m], velocities [m/s] and times [s] of an arm: beyond 1e6 the file is broken (and
    // squares of 1e154 and more overflow in the fit).
    for (std::size_t c = 1; c < names.size(); ++c)
      if (std::abs(row[col[c]]) > 1e6)
        throw InputError(fmt::format("{}: row {}: column '{}': {:g} is beyond +-1e6", table.source,
                                     r + 1, names[c], row[col[c]]));
    const double t = row[col[1]];
    if (!d.t.empty() && !(t > d.t.back()))
      throw InputError(fmt::format(
          "{}: row {}: demonstration {}: expected strictly increasing time, got {} after {}",
          table.source, r + 1, id, t, d.t.back()));
    d.t.push_back(t);
    d.x.emplace_back(row[col[2]], row[col[3]], row[col[4]]);
    d.xdot.emplace_back(row[col[5]], row[col[6]], row[col[7]]);
  }
  for (const auto& d : demos)
    if (d.size() < min_samples)
      throw InputError(fmt::format("{}: demonstration {}: expected at least {} samples, got {}",
                                   table.source, d.id, min_samples, d.size()));
  return demos;
}

std::vector<Demonstration> read_demonstrations(const std::filesystem::path& path) {
  return demonstrations_from_table(read_csv(path));
}

std::string format_demonstrations(const std::vector<Demonstration>& demos) {
  std::vector<std::vector<double>> rows;
  for (const auto& d : demos)
    for (std::size_t i = 0; i < d.size(); ++i)
      rows.push_back({static_cast<double>(d.id), d.t[i], d.x[i].x(), d.x[i].y(), d.x[i].z(),
                      d.xdot[i].x(), d.xdot[i].y(), d.xdot[i].z()});
  return format_csv({"demo", "t", "x", "y", "z", "vx", "vy", "vz"}, rows);
}

DemoSummary summarize_demonstrations(const std::vector<Demonstration>& demos,
                                     double end_tolerance) {
  if (demos.empty())
    throw InputError("demonstrations: expected at least one demonstration, got none");
  DemoSummary s;
  s.x_star.setZero();
  Vec3 dir_sum = Vec3::Zero();
  for (const auto& d : demos) {
    if (d.size() < 3 || d.x.size() != d.size() || d.xdot.size() != d.size())
      throw InputError(
          fmt::format("demonstration {}: expected at least 3 samples, got {}", d.id, d.size()));
    for (std::size_t i = 0; i < d.size(); ++i)
      if (!std::isfinite(d.t[i]) || !d.x[i].allFinite() || !d.xdot[i].allFinite())
        throw InputError(
            fmt::format("demonstration {}: sample {}: expected finite values", d.id, i));
    const double speed = d.xdot.back().norm();
    if (!(speed > 0.05))
      throw InputError(fmt::format(
          "demonstration {}: expected a non-zero speed at the ball (> 0.05 m/s), got {} m/s", d.id,
          speed));
    s.x_star += d.x.back();
    dir_sum += d.xdot.back() / speed;
    s.hitting_speed += speed;
  }
  const double n = static_cast<double>(demos.size());
  s.x_star /= n;
  s.hitting_speed /= n;
  for (const auto& d : demos) s.end_spread = std::max(s.end_spread, (d.x.back() - s.x_star).norm());
  if (s.end_spread > end_tolerance)
    throw InputError(
        fmt::format("demonstrations: expected a common end point (all within {} m of their mean), "
                    "got a spread of {} m",
                    end_tolerance, s.end_spread));
  Vec3 horizontal(dir_sum.x(), dir_sum.y(), 0.0);
  if (horizontal.norm() < 0.5 * n)
    throw InputError(
        "demonstrations: expected a common, mostly horizontal approach direction at the ball, got "
        "none");
  s.psi0 = horizontal.normalized();
  for (const auto& d : demos) {
    const double c = d.xdot.back().normalized().dot(s.psi0);
    if (c < std::cos(30.0 * std::numbers::pi / 180.0))
      throw InputError(
          fmt::format("demonstration {}: expected the final direction within 30 degrees of psi0, "
                      "got {} degrees",
                      d.id, std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi));
  }
  return s;
}

}  // namespace mg::ds
