#include "robot/arm_model.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/error.hpp"

namespace mg::robot {
namespace {

Vector7 from_array(const std::array<double, kNumJoints>& a) { return Vector7(a.data()); }

}  // namespace

ArmModel::ArmModel(const WamMount& mount) : mount_(mount) {
  mount_.validate();
  world_from_shoulder_ = robot::shoulder_in_world(mount_.base_position, mount_.base_yaw);
  flange_from_face_ = club_face_in_flange(mount_.club);
  lower_ = from_array(kJointLower);
  upper_ = from_array(kJointUpper);
  vel_limit_ = from_array(kVelocityLimit);
  torque_limit_ = from_array(kTorqueLimit);
  armature_ = from_array(kArmature);
  damping_ = from_array(kDamping);
  inertials_ = kLinkInertials;
  inertials_[kNumJoints - 1] =
      combine_inertials(kLinkInertials[kNumJoints - 1], club_inertial(mount_.club));
  gravity_ = world_from_shoulder_.linear().transpose() * Eigen::Vector3d(0.0, 0.0, -9.81);
}

ArmModel::ArmModel(const WamMount& mount, const JointParameters& joints) : ArmModel(mount) {
  lower_ = joints.lower;
  upper_ = joints.upper;
  armature_ = joints.armature;
  damping_ = joints.damping;
  torque_limit_ = joints.torque_limit;
  gravity_ = world_from_shoulder_.linear().transpose() * joints.gravity_world;
}

Eigen::Isometry3d dh_flange_pose(const ArmModel& arm, const Vector7& q) {
  return arm.shoulder_in_world() * dh_forward_kinematics(q);
}

Eigen::Isometry3d dh_club_pose(const ArmModel& arm, const Vector7& q) {
  return arm.shoulder_in_world() * dh_forward_kinematics(q) * arm.face_in_flange();
}

void dh_club_jacobian(const ArmModel& arm, const Vector7& q, Eigen::Isometry3d& pose,
                      Matrix67& jacobian) {
  // Geometric Jacobian: column i = [z_{i-1} x (p_face - p_{i-1}); z_{i-1}], world frame.
  Eigen::Isometry3d t = arm.shoulder_in_world();
  std::array<Eigen::Vector3d, kNumJoints> axis, origin;
  for (int i = 0; i < kNumJoints; ++i) {
    axis[static_cast<std::size_t>(i)] = t.linear().col(2);
    origin[static_cast<std::size_t>(i)] = t.translation();
    t = t * dh_link_transform(i + 1, q(i));
  }
  pose = t * arm.face_in_flange();
  for (int i = 0; i < kNumJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    jacobian.block<3, 1>(0, i) = axis[k].cross(pose.translation() - origin[k]);
    jacobian.block<3, 1>(3, i) = axis[k];
  }
}

}  // namespace mg::robot
