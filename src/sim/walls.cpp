#include "sim/walls.hpp"

#include <algorithm>
#include <cmath>

namespace mg::sim {
namespace {

using Vec3 = std::array<double, 3>;

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// The point of a prism nearest to `p`, and whether `p` lies inside it.
struct Nearest {
  Vec3 point{};
  Vec3 normal{};          ///< unit, from the prism towards p
  double distance = 0.0;  ///< [m] (0 inside)
  bool inside = false;
};

Nearest nearest(const WallPrism& w, const Vec3& p) {
  const double rx = p[0] - w.cx, ry = p[1] - w.cy;
  const double lx = w.cos_yaw * rx + w.sin_yaw * ry;
  const double ly = -w.sin_yaw * rx + w.cos_yaw * ry;
  double qx = std::clamp(lx, -w.hx, w.hx), qy = std::clamp(ly, -w.hy, w.hy);
  const double qz = std::clamp(p[2], w.bottom, w.top);
  Nearest n;
  double nx = lx - qx, ny = ly - qy, nz = p[2] - qz;
  if (nx == 0.0 && ny == 0.0 && nz == 0.0) {
    // The centre is inside: out through the nearest side face (the swept check makes this rare).
    n.inside = true;
    const double gaps[4] = {w.hx - lx, lx + w.hx, w.hy - ly, ly + w.hy};
    const int side = static_cast<int>(std::min_element(gaps, gaps + 4) - gaps);
    qx = side == 0 ? w.hx : side == 1 ? -w.hx : lx;
    qy = side == 2 ? w.hy : side == 3 ? -w.hy : ly;
    nx = side == 0 ? 1.0 : side == 1 ? -1.0 : 0.0;
    ny = side == 2 ? 1.0 : side == 3 ? -1.0 : 0.0;
  } else {
    n.distance = std::sqrt(nx * nx + ny * ny + nz * nz);
    nx /= n.distance;
    ny /= n.distance;
    nz /= n.distance;
  }
  n.point = {w.cx + w.cos_yaw * qx - w.sin_yaw * qy, w.cy + w.sin_yaw * qx + w.cos_yaw * qy, qz};
  n.normal = {w.cos_yaw * nx - w.sin_yaw * ny, w.sin_yaw * nx + w.cos_yaw * ny, nz};
  return n;
}

/// The ball against one prism, touching at `at` (the nearest point's plane): the impulse on v
/// and w, and the centre moved out of the prism. Returns the speed into the face (0: leaving).
double bounce(const Walls& walls, const field::Field& field, const WallPrism& prism,
              const Nearest& at, Vec3& c, Vec3& v, Vec3& w) {
  const Vec3& n = at.normal;
  const double r = walls.radius;
  const bool face = std::abs(n[2]) < 1e-9;
  const double into = wall_impulse(n, prism.restitution, r, walls.inertia_ratio, v, w);
  // Out of the prism: mirrored off the contact plane by the restitution when the ball came in.
  const double depth = r - dot({c[0] - at.point[0], c[1] - at.point[1], c[2] - at.point[2]}, n);
  if (depth > 0.0) {
    const double push = depth * (into > 0.0 ? 1.0 + prism.restitution : 1.0);
    const double ground_before = face ? field.height(c[0], c[1]) : 0.0;
    for (int i = 0; i < 3; ++i) c[i] += push * n[i];
    if (face) c[2] += field.height(c[0], c[1]) - ground_before;
  }
  return into;
}

}  // namespace

double wall_impulse(const Vec3& n, double restitution, double r, double k, Vec3& v, Vec3& w) {
  const double vn = dot(v, n);
  if (!(vn < 0.0)) return 0.0;
  const double into = -vn;
  const bool face = std::abs(n[2]) < 1e-9;
  const double jn = (1.0 + restitution) * into;  // normal impulse per unit mass [m/s]
  const Vec3 arm{-r * n[0], -r * n[1], -r * n[2]};
  const Vec3 spin_part = cross(w, arm);
  Vec3 slip{v[0] + spin_part[0], v[1] + spin_part[1], v[2] + spin_part[2]};
  const double slip_n = dot(slip, n);
  for (int i = 0; i < 3; ++i) slip[i] -= slip_n * n[i];
  Vec3 j{};      // friction impulse per unit mass [m/s]
  Vec3 j_lin{};  // its part that changes the centre's velocity
  if (face) {
    // Along the face (horizontal): the centre and the spin both slow the slip; across it
    // (vertical): the spin alone (no lift, see walls.hpp).
    const Vec3 t1{-n[1], n[0], 0.0};
    const double u1 = dot(slip, t1), u2 = slip[2];
    // Friction only slows the centre along the face: side spin never speeds the ball up.
    const double j1 = u1 * dot(v, t1) > 0.0 ? -u1 / (1.0 + 1.0 / k) : 0.0, j2 = -u2 * k;
    const double size = std::hypot(j1, j2);
    const double s = size > kWallFriction * jn ? kWallFriction * jn / size : 1.0;
    j = {s * j1 * t1[0], s * j1 * t1[1], s * j2};
    j_lin = {s * j1 * t1[0], s * j1 * t1[1], 0.0};
  } else {
    const double size = std::sqrt(dot(slip, slip)) / (1.0 + 1.0 / k);
    const double s = size > kWallFriction * jn ? kWallFriction * jn / size : 1.0;
    for (int i = 0; i < 3; ++i) j[i] = -s * slip[i] / (1.0 + 1.0 / k);
    j_lin = j;
  }
  const Vec3 dw = cross(arm, j);
  for (int i = 0; i < 3; ++i) {
    v[i] += j_lin[i] + jn * n[i];
    w[i] += dw[i] / (k * r * r);
  }
  return into;
}

RollingRebound rolling_rebound(double restitution, double incidence, double inertia_ratio) {
  // A unit ball rolling at unit speed into the face y = 0 from y > 0 (normal +y), then the slide
  // on level ground until it rolls again: angular momentum about the contact point is kept, so
  // it rolls at (v + k r w x z) / (1 + k).
  const double k = inertia_ratio;
  Vec3 v{std::sin(incidence), -std::cos(incidence), 0.0};
  Vec3 w{-v[1], v[0], 0.0};  // z x v / r
  wall_impulse({0.0, 1.0, 0.0}, restitution, 1.0, k, v, w);
  const double vx = (v[0] + k * w[1]) / (1.0 + k), vy = (v[1] - k * w[0]) / (1.0 + k);
  return {std::hypot(vx, vy), std::atan2(std::abs(vx), vy)};
}

Walls make_walls(const field::Field& f) {
  Walls walls;
  walls.radius = f.ball.radius;
  const auto& b = f.bounds;
  const auto [z_min, z_max] = field::height_range(f);
  const double bottom = z_min - 0.05;
  const double cx = 0.5 * (b[0] + b[1]), cy = 0.5 * (b[2] + b[3]);
  const double rx = 0.5 * (b[1] - b[0]), ry = 0.5 * (b[3] - b[2]);
  const double t = f.borders.thickness;
  const auto add = [&walls](double x, double y, double hx, double hy, double c, double s, double lo,
                            double hi, double e) {
    walls.prisms[static_cast<std::size_t>(walls.count++)] = {x, y, hx, hy, c, s, lo, hi, e};
  };
  const double top = z_max + f.borders.height, e = f.borders.restitution;
  add(b[0] - 0.5 * t, cy, 0.5 * t, ry + t, 1.0, 0.0, bottom, top, e);
  add(b[1] + 0.5 * t, cy, 0.5 * t, ry + t, 1.0, 0.0, bottom, top, e);
  add(cx, b[2] - 0.5 * t, rx, 0.5 * t, 1.0, 0.0, bottom, top, e);
  add(cx, b[3] + 0.5 * t, rx, 0.5 * t, 1.0, 0.0, bottom, top, e);
  for (const field::Obstacle& ob : f.obstacles) {
    const field::Footprint fp = ob.footprint();
    add(fp.center[0], fp.center[1], fp.half[0], fp.half[1], std::cos(fp.yaw), std::sin(fp.yaw),
        bottom, field::obstacle_top(f, ob), ob.restitution);
  }
  double thinnest = walls.radius;
  for (int i = 0; i < walls.count; ++i) {
    const WallPrism& p = walls.prisms[static_cast<std::size_t>(i)];
    thinnest = std::min(thinnest, 2.0 * std::min(p.hx, p.hy));
  }
  walls.sample_spacing = 0.5 * thinnest;
  return walls;
}

WallImpact resolve_walls(const Walls& walls, const field::Field& field, const Vec3& previous,
                         Vec3& c, Vec3& v, Vec3& w) {
  WallImpact impact;
  const double r = walls.radius;
  // The first point of the swept path that touches a prism (so a fast ball cannot pass a thin
  // wall within one step), then the corner's other faces from where the ball ends up.
  Vec3 path{c[0] - previous[0], c[1] - previous[1], c[2] - previous[2]};
  const double length = std::sqrt(dot(path, path));
  int samples = std::max(1, static_cast<int>(std::ceil(length / walls.sample_spacing)));
  for (int round = 0; round < 4; ++round) {
    int hit = -1;
    Nearest at;
    for (int s = 1; s <= samples && hit < 0; ++s) {
      const double f = static_cast<double>(s) / samples;
      const Vec3 p{c[0] - (1.0 - f) * path[0], c[1] - (1.0 - f) * path[1],
                   c[2] - (1.0 - f) * path[2]};
      double deepest = r;
      for (int i = 0; i < walls.count; ++i) {
        const Nearest n = nearest(walls.prisms[static_cast<std::size_t>(i)], p);
        const double d = n.inside ? -1.0 : n.distance;
        if (d < deepest) {
          deepest = d;
          hit = i;
          at = n;
        }
      }
    }
    if (hit < 0) break;
    const double into =
        bounce(walls, field, walls.prisms[static_cast<std::size_t>(hit)], at, c, v, w);
    if (into > impact.normal_speed) impact = {into, hit};
    samples = 1;
    path = {0.0, 0.0, 0.0};
  }
  return impact;
}

double wall_clearance(const Walls& walls, const Vec3& c) {
  double clear = 1e300;
  for (int i = 0; i < walls.count; ++i) {
    const Nearest n = nearest(walls.prisms[static_cast<std::size_t>(i)], c);
    clear = std::min(clear, (n.inside ? 0.0 : n.distance) - walls.radius);
  }
  return clear;
}

}  // namespace mg::sim
