#include "robot/wam_model.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/check.hpp"

namespace mg::robot {

void WamMount::validate() const {
  require_in_range("mount.base_position[0]", base_position[0], -10.0, 10.0);
  require_in_range("mount.base_position[1]", base_position[1], -10.0, 10.0);
  require_in_range("mount.base_position[2]", base_position[2], -2.0, 3.0);
  require_in_range("mount.base_yaw", base_yaw, -2.0 * kPi, 2.0 * kPi);
  require_in_range("mount.club.shaft_length", club.shaft_length, 0.2, 1.5);
  require_in_range("mount.club.shaft_radius", club.shaft_radius, 1e-3, 0.03);
  require_in_range("mount.club.shaft_mass", club.shaft_mass, 1e-3, 2.0);
  require_in_range("mount.club.lie_angle", club.lie_angle, 0.5, kPi / 2);
  require_in_range("mount.club.head_length", club.head_length, 0.02, 0.3);
  require_in_range("mount.club.head_thickness", club.head_thickness, 0.005, 0.1);
  require_in_range("mount.club.head_height", club.head_height, 0.005, 0.1);
  require_in_range("mount.club.head_mass", club.head_mass, 1e-3, 2.0);
  require_in_range("mount.club.face_restitution", club.face_restitution, 0.05, 0.99);
  for (std::size_t j = 0; j < joint_friction.size(); ++j)
    require_in_range(fmt::format("mount.joint_friction[{}]", j), joint_friction[j], 0.0, 20.0);
}

std::array<double, 3> Stance::to_world(const std::array<double, 3>& p) const {
  if (yaw == 0.0) return {p[0] + position[0], p[1] + position[1], p[2] + position[2]};
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * p[0] - s * p[1] + position[0], s * p[0] + c * p[1] + position[1], p[2] + position[2]};
}

std::array<double, 3> Stance::to_local(const std::array<double, 3>& p) const {
  const double x = p[0] - position[0], y = p[1] - position[1], z = p[2] - position[2];
  if (yaw == 0.0) return {x, y, z};
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * x + s * y, -s * x + c * y, z};
}

WamMount mount_at(const WamMount& local, const Stance& stance) {
  if (stance.identity()) return local;
  WamMount m = local;
  m.base_position = stance.to_world(local.base_position);
  // The base's yaw kept in (-pi, pi] so that a stance of any yaw is a valid mount.
  m.base_yaw = std::remainder(local.base_yaw + stance.yaw, 2.0 * kPi);
  return m;
}

}  // namespace mg::robot
