#include "teacher/bank_shots.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "belief/prior.hpp"
#include "sim/walls.hpp"

namespace mg::teacher {
namespace {

using Vec = std::array<double, 2>;

Vec operator-(Vec a, Vec b) { return {a[0] - b[0], a[1] - b[1]}; }
Vec operator+(Vec a, Vec b) { return {a[0] + b[0], a[1] + b[1]}; }
Vec operator*(double k, Vec a) { return {k * a[0], k * a[1]}; }
double dot(Vec a, Vec b) { return a[0] * b[0] + a[1] * b[1]; }
double norm(Vec a) { return std::hypot(a[0], a[1]); }

/// A straight piece of the line the ball's centre bounces on: a border's or an obstacle face's
/// a ball radius out, from p0 to p1, its normal n pointing to the side the ball comes from.
struct Mirror {
  Vec p0, p1, n;
  double restitution;
  /// Where the ball aims to reach `p` off this face: `p` mirrored, its distance from the face
  /// scaled by `ratio` (tan of the rolling ball's angle out / in, sim::rolling_rebound; 1: the
  /// mirror law).
  Vec image(Vec p, double ratio) const { return p - (1.0 + ratio) * dot(p - p0, n) * n; }
  /// The rebound ratio for a ball arriving along `d`.
  double ratio(Vec d) const {
    const double i = std::clamp(
        std::acos(std::min(1.0, std::abs(dot(d, n)) / std::max(norm(d), 1e-12))), 0.01, 1.55);
    const double out = sim::rolling_rebound(restitution, i).angle;
    return out < 1.5 ? std::tan(out) / std::tan(i) : -1.0;  // -1: it rolls back into the face
  }
  /// Where the segment a -> b crosses the mirror coming from its free side (nothing: it does not).
  std::optional<Vec> hit(Vec a, Vec b) const {
    const double da = dot(a - p0, n), db = dot(b - p0, n);
    if (!(da > 0.0 && db < 0.0)) return std::nullopt;
    const Vec p = a + (da / (da - db)) * (b - a);
    const Vec along = p1 - p0;
    const double u = dot(p - p0, along) / dot(along, along);
    if (u < 0.0 || u > 1.0) return std::nullopt;
    return p;
  }
};

std::vector<Mirror> mirrors(const field::Field& f) {
  const auto& b = f.bounds;
  const double r = f.ball.radius, e = f.borders.restitution;
  std::vector<Mirror> out = {
      {{b[0] + r, b[2] + r}, {b[0] + r, b[3] - r}, {1.0, 0.0}, e},
      {{b[1] - r, b[2] + r}, {b[1] - r, b[3] - r}, {-1.0, 0.0}, e},
      {{b[0] + r, b[2] + r}, {b[1] - r, b[2] + r}, {0.0, 1.0}, e},
      {{b[0] + r, b[3] - r}, {b[1] - r, b[3] - r}, {0.0, -1.0}, e},
  };
  for (const auto& o : f.obstacles) {
    const field::Footprint fp = o.footprint();
    const Vec ex{std::cos(fp.yaw), std::sin(fp.yaw)}, ey{-ex[1], ex[0]};
    // The four flat faces, a ball radius out (the rounded corners are left out).
    for (int sign : {-1, 1}) {
      const Vec nx = static_cast<double>(sign) * ex, ny = static_cast<double>(sign) * ey;
      const Vec cx = fp.center + (fp.half[0] + r) * nx, cy = fp.center + (fp.half[1] + r) * ny;
      out.push_back({cx - fp.half[1] * ey, cx + fp.half[1] * ey, nx, o.restitution});
      out.push_back({cy - fp.half[0] * ex, cy + fp.half[0] * ex, ny, o.restitution});
    }
  }
  return out;
}

/// The prior launch speed that rolls the legs (in order, `path` from the ball to the hole) and
/// arrives at `arrival`: backwards from the hole, each bounce keeps the share of the rolling speed
/// the wall model gives (sim::rolling_rebound).
double launch_speed(const std::vector<Vec>& path, const std::vector<const Mirror*>& hits,
                    double a_roll, double arrival) {
  double v2 = arrival * arrival;
  for (std::size_t k = path.size() - 1; k >= 1; --k) {
    v2 += 2.0 * a_roll * norm(path[k] - path[k - 1]);
    if (k >= 2) {  // path[k - 1] is a bounce: undo it
      const Mirror& m = *hits[k - 2];
      const Vec d = path[k - 1] - path[k - 2];
      const double i = std::acos(std::min(1.0, std::abs(dot(d, m.n)) / std::max(norm(d), 1e-9)));
      const double keep = sim::rolling_rebound(m.restitution, i).speed;
      v2 /= std::max(keep * keep, 0.05);
    }
  }
  return 7.0 / 5.0 * std::sqrt(v2);  // a launched ball keeps 5/7 of its speed once it rolls
}

}  // namespace

std::vector<BankShot> bank_shots(const field::Field& f, std::array<double, 2> ball,
                                 std::array<double, 2> hole, double arrival) {
  const double a_roll = belief::rolling_deceleration(f);
  // The legs may pass a ball radius from anything but the faces they bounce on (0.99: the bounce
  // point itself is exactly a radius away).
  const double clearance = 0.99 * f.ball.radius;
  const auto clear = [&](const std::vector<Vec>& path) {
    for (std::size_t k = 1; k < path.size(); ++k)
      if (field::line_blocked(f, path[k - 1], path[k], clearance)) return false;
    return true;
  };
  const auto add = [&](std::vector<BankShot>& out, const std::vector<Vec>& path,
                       const std::vector<const Mirror*>& hits) {
    if (!clear(path)) return;
    double length = 0.0;
    for (std::size_t k = 1; k < path.size(); ++k) length += norm(path[k] - path[k - 1]);
    out.push_back({std::atan2(path[1][1] - ball[1], path[1][0] - ball[0]),
                   launch_speed(path, hits, a_roll, arrival), length,
                   static_cast<int>(hits.size())});
  };
  const std::vector<Mirror> ms = mirrors(f);
  std::vector<BankShot> one, two;
  // The bounce points: from the mirror law, then eight times with the rebound ratio of the
  // incidence found (a rolling ball leaves a face closer to it than it came: the wall keeps its
  // spin, sim/walls).
  constexpr int kRefinements = 8;
  for (const Mirror& m : ms) {
    if (dot(hole - m.p0, m.n) <= 0.0) continue;
    double ratio = 1.0;
    std::optional<Vec> b;
    for (int it = 0; it <= kRefinements && ratio > 0.0; ++it) {
      b = m.hit(ball, m.image(hole, ratio));
      if (!b) break;
      ratio = m.ratio(*b - ball);
    }
    if (b && ratio > 0.0) add(one, {ball, *b, hole}, {&m});
  }
  for (const Mirror& m1 : ms)
    for (const Mirror& m2 : ms) {
      if (&m1 == &m2 || dot(hole - m2.p0, m2.n) <= 0.0) continue;
      double r1 = 1.0, r2 = 1.0;
      std::optional<Vec> b1, b2;
      for (int it = 0; it <= kRefinements && r1 > 0.0 && r2 > 0.0; ++it) {
        const Vec h2 = m2.image(hole, r2);
        b1 = m1.hit(ball, m1.image(h2, r1));
        b2 = b1 ? m2.hit(*b1, h2) : std::nullopt;
        if (!b2) break;
        r1 = m1.ratio(*b1 - ball);
        r2 = m2.ratio(*b2 - *b1);
      }
      if (b1 && b2 && r1 > 0.0 && r2 > 0.0) add(two, {ball, *b1, *b2, hole}, {&m1, &m2});
    }
  const auto shorter = [](const BankShot& x, const BankShot& y) {
    return x.path_length < y.path_length;
  };
  std::sort(one.begin(), one.end(), shorter);
  std::sort(two.begin(), two.end(), shorter);
  one.insert(one.end(), two.begin(), two.end());
  return one;
}

}  // namespace mg::teacher
