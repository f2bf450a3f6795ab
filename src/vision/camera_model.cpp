#include "vision/camera_model.hpp"

#include <cmath>
#include <limits>

namespace mg::vision {

Eigen::Matrix3d CameraModel::K() const {
  Eigen::Matrix3d k;
  k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return k;
}

CameraModel camera_from_spec(const CameraSpec& s) {
  CameraModel c;
  c.name = s.name;
  c.width = s.width;
  c.height = s.height;
  constexpr double kPi = 3.14159265358979323846;
  c.fy = 0.5 * s.height / std::tan(0.5 * s.fovy_deg * kPi / 180.0);
  c.fx = c.fy;
  c.cx = 0.5 * s.width - 0.5;
  c.cy = 0.5 * s.height - 0.5;
  c.dist = s.distortion.coefficients();
  const Eigen::Vector3d pos(s.position.data()), at(s.look_at.data()), up(s.up.data());
  const Eigen::Vector3d forward = (at - pos).normalized();
  const Eigen::Vector3d right = forward.cross(up).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  c.R.row(0) = right;
  c.R.row(1) = down;
  c.R.row(2) = forward;
  c.t = -c.R * pos;
  c.rate_hz = s.rate_hz;
  c.latency = s.latency;
  return c;
}

Eigen::Vector2d distort(const std::array<double, 5>& d, const Eigen::Vector2d& p) {
  const double x = p.x(), y = p.y(), r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
  return {x * radial + 2.0 * d[2] * x * y + d[3] * (r2 + 2.0 * x * x),
          y * radial + d[2] * (r2 + 2.0 * y * y) + 2.0 * d[3] * x * y};
}

Eigen::Vector2d undistort(const std::array<double, 5>& d, const Eigen::Vector2d& distorted) {
  if (d == std::array<double, 5>{}) return distorted;
  Eigen::Vector2d p = distorted;
  for (int i = 0; i < 20; ++i) p += distorted - distort(d, p);
  return p;
}

std::optional<Eigen::Vector2d> project(const CameraModel& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = c.R * p + c.t;
  if (!(q.z() > 1e-3)) return std::nullopt;
  const Eigen::Vector2d n = distort(c.dist, {q.x() / q.z(), q.y() / q.z()});
  return Eigen::Vector2d(c.fx * n.x() + c.cx, c.fy * n.y() + c.cy);
}

bool in_image(const CameraModel& c, const Eigen::Vector2d& px, double margin) {
  return px.x() >= -0.5 + margin && px.y() >= -0.5 + margin && px.x() <= c.width - 0.5 - margin &&
         px.y() <= c.height - 0.5 - margin;
}

Ray pixel_ray(const CameraModel& c, const Eigen::Vector2d& px) {
  const Eigen::Vector2d n = undistort(c.dist, {(px.x() - c.cx) / c.fx, (px.y() - c.cy) / c.fy});
  return {c.centre(), (c.R.transpose() * Eigen::Vector3d(n.x(), n.y(), 1.0)).normalized()};
}

std::optional<Eigen::Vector3d> triangulate(const Ray& a, const Ray& b) {
  // Minimise |a.o + s a.d - b.o - u b.d|^2 over s, u.
  const Eigen::Vector3d w = a.origin - b.origin;
  const double aa = a.direction.dot(a.direction), ab = a.direction.dot(b.direction),
               bb = b.direction.dot(b.direction);
  const double den = aa * bb - ab * ab;
  if (!(den > 1e-9)) return std::nullopt;
  const double da = a.direction.dot(w), db = b.direction.dot(w);
  const double s = (ab * db - bb * da) / den, u = (aa * db - ab * da) / den;
  if (s <= 0.0 || u <= 0.0) return std::nullopt;
  return 0.5 * ((a.origin + s * a.direction) + (b.origin + u * b.direction));
}

std::optional<Eigen::Vector3d> triangulate(const CameraModel& a, const Eigen::Vector2d& pa,
                                           const CameraModel& b, const Eigen::Vector2d& pb) {
  auto p = triangulate(pixel_ray(a, pa), pixel_ray(b, pb));
  if (!p) return std::nullopt;
  // Gauss-Newton on the four pixel residuals (numeric Jacobian: 3 extra projections per step).
  Eigen::Vector3d x = *p;
  const auto residual = [&](const Eigen::Vector3d& q, Eigen::Vector4d& r) {
    const auto ua = project(a, q), ub = project(b, q);
    if (!ua || !ub) return false;
    r << *ua - pa, *ub - pb;
    return true;
  };
  for (int it = 0; it < 5; ++it) {
    Eigen::Vector4d r0;
    if (!residual(x, r0)) return std::nullopt;
    Eigen::Matrix<double, 4, 3> J;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d dx = x;
      dx[k] += 1e-6;
      Eigen::Vector4d r1;
      if (!residual(dx, r1)) return std::nullopt;
      J.col(k) = (r1 - r0) / 1e-6;
    }
    const Eigen::Vector3d step = (J.transpose() * J).ldlt().solve(-J.transpose() * r0);
    x += step;
    if (step.norm() < 1e-9) break;
  }
  return x;
}

double reprojection_error(const CameraModel& a, const Eigen::Vector2d& pa, const CameraModel& b,
                          const Eigen::Vector2d& pb, const Eigen::Vector3d& p) {
  const auto ua = project(a, p), ub = project(b, p);
  if (!ua || !ub) return std::numeric_limits<double>::infinity();
  return std::max((*ua - pa).norm(), (*ub - pb).norm());
}

std::optional<Eigen::Vector3d> intersect_surface(const CameraModel& c, const Eigen::Vector2d& px,
                                                 const field::Field& field, double above) {
  const Ray ray = pixel_ray(c, px);
  if (!(ray.direction.z() < -1e-6)) return std::nullopt;
  // Fixed point: the plane z = height(x, y) + above under the last estimate.
  double z = field.height(ray.origin.x(), ray.origin.y()) + above;
  Eigen::Vector3d p = ray.origin;
  for (int i = 0; i < 8; ++i) {
    const double s = (z - ray.origin.z()) / ray.direction.z();
    if (s <= 0.0) return std::nullopt;
    p = ray.origin + s * ray.direction;
    z = field.height(p.x(), p.y()) + above;
  }
  const auto& b = field.bounds;
  if (p.x() < b[0] || p.x() > b[1] || p.y() < b[2] || p.y() > b[3]) return std::nullopt;
  return p;
}

}  // namespace mg::vision
