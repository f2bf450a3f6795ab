#include "robot/kinematics.hpp"

#include <cmath>

namespace mg::robot {

Eigen::Isometry3d dh_link_transform(int i, double q) {
  const DhRow& row = kDhTable[static_cast<std::size_t>(i - 1)];
  const double ct = std::cos(q), st = std::sin(q);
  const double ca = std::cos(row.alpha), sa = std::sin(row.alpha);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() << ct, -st * ca, st * sa,  //
      st, ct * ca, -ct * sa,            //
      0.0, sa, ca;
  t.translation() << row.a * ct, row.a * st, row.d;
  return t;
}

void dh_link_frames(const Vector7& q, std::array<Eigen::Isometry3d, kNumJoints>& frames) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int i = 1; i <= kNumJoints; ++i) {
    t = t * dh_link_transform(i, q(i - 1));
    frames[static_cast<std::size_t>(i - 1)] = t;
  }
}

Eigen::Isometry3d dh_forward_kinematics(const Vector7& q) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (int i = 1; i <= kNumJoints; ++i) t = t * dh_link_transform(i, q(i - 1));
  return t;
}

namespace {

// Heel-to-toe axis h and face-up axis u of the head in the flange frame; the face normal is -y.
// The shaft runs along +z from the flange down to the heel, so "up the shaft" is -z; the toe
// points away from the shaft top: angle(-z, h) = pi - lie.
Eigen::Vector3d toe_axis(const ClubGeometry& c) {
  return {std::sin(c.lie_angle), 0.0, std::cos(c.lie_angle)};
}
Eigen::Vector3d up_axis(const ClubGeometry& c) {
  return {std::cos(c.lie_angle), 0.0, -std::sin(c.lie_angle)};
}

Eigen::Vector3d head_centre(const ClubGeometry& c) {
  return Eigen::Vector3d(0.0, 0.0, c.shaft_length) + 0.5 * c.head_length * toe_axis(c);
}

Eigen::Matrix3d head_rotation(const ClubGeometry& c) {
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d(0.0, -1.0, 0.0);
  r.col(1) = -toe_axis(c);
  r.col(2) = up_axis(c);
  return r;
}

Eigen::Matrix3d to_matrix(const std::array<double, 6>& i) {
  Eigen::Matrix3d m;
  m << i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2];
  return m;
}

std::array<double, 6> from_matrix(const Eigen::Matrix3d& m) {
  return {m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(0, 2), m(1, 2)};
}

}  // namespace

Eigen::Isometry3d club_face_in_flange(const ClubGeometry& c) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = head_rotation(c);
  t.translation() = head_centre(c) + 0.5 * c.head_thickness * t.linear().col(0);
  return t;
}

LinkInertial combine_inertials(const LinkInertial& a, const LinkInertial& b) {
  const double m = a.mass + b.mass;
  const Eigen::Vector3d ca(a.com.data()), cb(b.com.data());
  const Eigen::Vector3d c = (a.mass * ca + b.mass * cb) / m;
  auto shifted = [&c](const LinkInertial& l, const Eigen::Vector3d& cl) {
    const Eigen::Vector3d d = cl - c;
    return Eigen::Matrix3d(to_matrix(l.inertia) +
                           l.mass *
                               (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  const Eigen::Matrix3d inertia = shifted(a, ca) + shifted(b, cb);
  return {m, {c.x(), c.y(), c.z()}, from_matrix(inertia)};
}

LinkInertial club_inertial(const ClubGeometry& c) {
  // Shaft: solid cylinder along z from the flange.
  const double r = c.shaft_radius, l = c.shaft_length, ms = c.shaft_mass;
  const double it = ms * (3.0 * r * r + l * l) / 12.0;
  const LinkInertial shaft{ms, {0.0, 0.0, 0.5 * l}, {it, it, 0.5 * ms * r * r, 0.0, 0.0, 0.0}};
  // Head: solid box, axes (face normal, heel, up) = head_rotation.
  const double mh = c.head_mass, tx = c.head_thickness, ty = c.head_length, tz = c.head_height;
  const Eigen::Vector3d local(mh * (ty * ty + tz * tz) / 12.0, mh * (tx * tx + tz * tz) / 12.0,
                              mh * (tx * tx + ty * ty) / 12.0);
  const Eigen::Matrix3d rh = head_rotation(c);
  const Eigen::Matrix3d ih = rh * local.asDiagonal() * rh.transpose();
  const Eigen::Vector3d ch = head_centre(c);
  const LinkInertial head{mh, {ch.x(), ch.y(), ch.z()}, from_matrix(ih)};
  return combine_inertials(shaft, head);
}

Eigen::Isometry3d shoulder_in_world(const std::array<double, 3>& base_position, double base_yaw) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(base_yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() << base_position[0], base_position[1], base_position[2] + kShoulderHeight;
  return t;
}

Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

Eigen::Vector3d rotation_to_vector(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

}  // namespace mg::robot
