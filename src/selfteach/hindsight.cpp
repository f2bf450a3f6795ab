#include "selfteach/hindsight.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::selfteach {

void HindsightRules::validate() const {
  if (!(arrival_speed > 0.0 && arrival_speed < 5.0))
    throw InputError(
        fmt::format("hindsight: arrival speed: expected 0..5 m/s, got {}", arrival_speed));
  if (!(spacing > 0.0 && spacing < 10.0))
    throw InputError(fmt::format("hindsight: spacing: expected 0..10 m, got {}", spacing));
  if (!(min_speed >= 0.0 && min_speed < arrival_speed))
    throw InputError(
        fmt::format("hindsight: min_speed: expected 0..{} m/s, got {}", arrival_speed, min_speed));
}

std::array<double, 4> region_bounds(const field::Situations& region) {
  using field::RegionShape;
  if (region.shape == RegionShape::kLine)
    return {std::min(region.from[0], region.to[0]), std::max(region.from[0], region.to[0]),
            std::min(region.from[1], region.to[1]), std::max(region.from[1], region.to[1])};
  if (region.shape == RegionShape::kList) {
    std::array<double, 4> b{1e300, -1e300, 1e300, -1e300};
    for (const auto& p : region.points) {
      b[0] = std::min(b[0], p[0]);
      b[1] = std::max(b[1], p[0]);
      b[2] = std::min(b[2], p[1]);
      b[3] = std::max(b[3], p[1]);
    }
    return b;
  }
  return {region.x_range[0], region.x_range[1], region.y_range[0], region.y_range[1]};
}

double label_margin(const field::Situations& region) {
  const auto b = region_bounds(region);
  return 0.05 + 0.25 * std::max(b[1] - b[0], b[3] - b[2]);
}

bool in_label_zone(const field::Situations& region, std::array<double, 2> p, double margin) {
  const auto b = region_bounds(region);
  return p[0] >= b[0] - margin && p[0] <= b[1] + margin && p[1] >= b[2] - margin &&
         p[1] <= b[3] + margin;
}

namespace {

double horizontal_speed(const sim::BallSample& s) { return std::hypot(s.vx, s.vy); }

/// The samples before the ball's centre first comes within `radius` of the real hole.
std::size_t usable_samples(const std::vector<sim::BallSample>& t, std::array<double, 2> hole,
                           double radius) {
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::hypot(t[i].x - hole[0], t[i].y - hole[1]) < radius) return i;
  return t.size();
}

}  // namespace

std::vector<Label> hindsight_labels(const std::vector<sim::BallSample>& path,
                                    std::array<double, 2> ball, std::array<double, 2> real_hole,
                                    double hole_radius, double rolling_decel,
                                    const field::Situations& region, double margin, double angle,
                                    double speed, int putt, const HindsightRules& rules) {
  rules.validate();
  std::vector<Label> labels;
  std::size_t n = usable_samples(path, real_hole, hole_radius);
  if (n < 2) return labels;
  std::vector<sim::BallSample> continued;
  if (n < path.size()) {
    // Over the real hole the path is the hole's: continue the free roll straight instead.
    continued.assign(path.begin(), path.begin() + static_cast<std::ptrdiff_t>(n));
    const sim::BallSample last = path[n - 1];
    const double s0 = horizontal_speed(last);
    if (s0 > 0.0) {
      const double ux = last.vx / s0, uy = last.vy / s0;
      constexpr double kStep = 0.002;  // [m]
      const double reach = 2.0 * hole_radius + 0.02;
      for (double d = kStep; d <= reach + 1e-12; d += kStep) {
        const double s2 = s0 * s0 - 2.0 * std::max(0.0, rolling_decel) * d;
        if (s2 <= 0.0) break;
        const double s = std::sqrt(s2);
        continued.push_back({last.t + d / (0.5 * (s0 + s)), last.x + ux * d, last.y + uy * d,
                             last.z, ux * s, uy * s, 0.0});
      }
    }
    n = continued.size();
  }
  const std::vector<sim::BallSample>& trajectory = continued.empty() ? path : continued;
  const auto label_at = [&](const sim::BallSample& a, const sim::BallSample& b, double w) {
    Label l;
    l.hole = {a.x + w * (b.x - a.x), a.y + w * (b.y - a.y)};
    l.ball = ball;
    l.angle = angle;
    l.speed = speed;
    l.arrival_speed = horizontal_speed(a) + w * (horizontal_speed(b) - horizontal_speed(a));
    l.putt = putt;
    return l;
  };

  if (rules.learn_speed) {
    // The first fall of the speed through s* (the launch is faster, the ball slows as it rolls).
    const double s_star = rules.arrival_speed;
    for (std::size_t i = 1; i < n; ++i) {
      const double sa = horizontal_speed(trajectory[i - 1]), sb = horizontal_speed(trajectory[i]);
      if (sa > s_star && sb <= s_star) {
        const Label l = label_at(trajectory[i - 1], trajectory[i], (sa - s_star) / (sa - sb));
        if (in_label_zone(region, l.hole, margin)) labels.push_back(l);
        break;
      }
    }
    return labels;
  }

  if (region.shape == field::RegionShape::kLine) {
    // Crossings of the line through the region's ends, within the segment grown by `margin`.
    const double ux = region.to[0] - region.from[0], uy = region.to[1] - region.from[1];
    const double len = std::hypot(ux, uy);
    if (!(len > 0.0)) return labels;
    const double ex = ux / len, ey = uy / len;
    const auto side = [&](const sim::BallSample& s) {
      return ex * (s.y - region.from[1]) - ey * (s.x - region.from[0]);
    };
    for (std::size_t i = 1; i < n; ++i) {
      const double da = side(trajectory[i - 1]), db = side(trajectory[i]);
      if ((da > 0.0) == (db > 0.0) || da == db) continue;
      const Label l = label_at(trajectory[i - 1], trajectory[i], da / (da - db));
      const double along = ex * (l.hole[0] - region.from[0]) + ey * (l.hole[1] - region.from[1]);
      if (along >= -margin && along <= len + margin && l.arrival_speed > rules.min_speed)
        labels.push_back(l);
      break;  // a ball crossing back has met other ground: the first crossing only
    }
    return labels;
  }

  // A 2-D region: points of the path inside it, `spacing` apart along the path.
  double since_last = rules.spacing;
  for (std::size_t i = 1; i < n; ++i) {
    const auto& a = trajectory[i - 1];
    const auto& b = trajectory[i];
    since_last += std::hypot(b.x - a.x, b.y - a.y);
    if (since_last < rules.spacing || horizontal_speed(b) <= rules.min_speed) continue;
    if (!in_label_zone(region, {b.x, b.y}, margin)) continue;
    labels.push_back(label_at(a, b, 1.0));
    since_last = 0.0;
  }
  return labels;
}

}  // namespace mg::selfteach
