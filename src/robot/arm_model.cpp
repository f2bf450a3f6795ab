#include "robot/arm_model.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace mg::robot {
namespace {

Vector7 from_array(const std::array<double, kNumJoints>& a) { return Vector7(a.data()); }

int require_id(const mjModel* m, mjtObj type, const std::string& name) {
  const int id = mj_name2id(m, type, name.c_str());
  if (id < 0)
    throw InputError(fmt::format("WAM model: expected an element named '{}', found none", name));
  return id;
}

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

ArmModel::ArmModel(const mjModel* m, const WamMount& mount) : ArmModel(mount) {
  if (m == nullptr) throw InputError("WAM model: expected an mjModel, got a null pointer");
  for (int i = 0; i < kNumJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const int j = require_id(m, mjOBJ_JOINT, fmt::format("wam_j{}", i + 1));
    if (m->jnt_type[j] != mjJNT_HINGE)
      throw InputError(fmt::format("WAM model: joint wam_j{} is not a hinge", i + 1));
    qpos_adr_[k] = m->jnt_qposadr[j];
    dof_adr_[k] = m->jnt_dofadr[j];
    lower_(i) = m->jnt_range[2 * j];
    upper_(i) = m->jnt_range[2 * j + 1];
    armature_(i) = m->dof_armature[dof_adr_[k]];
    damping_(i) = m->dof_damping[dof_adr_[k]];
    actuator_id_[k] = require_id(m, mjOBJ_ACTUATOR, fmt::format("wam_m{}", i + 1));
    torque_limit_(i) = m->actuator_ctrlrange[2 * actuator_id_[k] + 1];
  }
  site_id_ = require_id(m, mjOBJ_SITE, "club_face");
  flange_body_ = require_id(m, mjOBJ_BODY, "wam_link7");
  gravity_ = world_from_shoulder_.linear().transpose() *
             Eigen::Vector3d(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);

  // The compiled link-1 frame at q = 0 must be world_T_0 * A_1(0): otherwise the mount passed
  // here is not the one the model was generated from.
  mjData* d = mj_makeData(m);
  if (d == nullptr) throw Error("MuJoCo: cannot allocate mjData");
  for (int i = 0; i < kNumJoints; ++i) d->qpos[qpos_adr_[static_cast<std::size_t>(i)]] = 0.0;
  mj_kinematics(m, d);
  const int link1 = require_id(m, mjOBJ_BODY, "wam_link1");
  Eigen::Isometry3d compiled = Eigen::Isometry3d::Identity();
  compiled.translation() = Eigen::Vector3d(d->xpos + 3 * link1);
  compiled.linear() = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(d->xmat + 9 * link1);
  mj_deleteData(d);
  const Eigen::Isometry3d expected = world_from_shoulder_ * dh_link_transform(1, 0.0);
  const double mismatch = (compiled.matrix() - expected.matrix()).cwiseAbs().maxCoeff();
  if (!(mismatch < 1e-9))
    throw InputError(fmt::format(
        "WAM model: the compiled base does not match the given mount (max difference {})",
        mismatch));
}

Vector7 joint_positions(const ArmModel& arm, const mjData* d) {
  Vector7 q;
  for (int i = 0; i < kNumJoints; ++i) q(i) = d->qpos[arm.qpos_address(i)];
  return q;
}

Vector7 joint_velocities(const ArmModel& arm, const mjData* d) {
  Vector7 qd;
  for (int i = 0; i < kNumJoints; ++i) qd(i) = d->qvel[arm.dof_address(i)];
  return qd;
}

void set_joint_positions(const ArmModel& arm, mjData* d, const Vector7& q) {
  for (int i = 0; i < kNumJoints; ++i) d->qpos[arm.qpos_address(i)] = q(i);
}

Eigen::Isometry3d club_pose(const ArmModel& arm, const mjData* d) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(d->site_xpos + 3 * arm.site_id());
  t.linear() = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(d->site_xmat + 9 * arm.site_id());
  return t;
}

Eigen::Isometry3d flange_pose(const ArmModel& arm, const mjData* d) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(d->xpos + 3 * arm.flange_body_id());
  t.linear() = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(d->xmat + 9 * arm.flange_body_id());
  return t;
}

void club_jacobian(const ArmModel& arm, const mjModel* m, mjData* d, Matrix67& jacobian) {
  const int nv = m->nv;
  mjMARKSTACK;
  mjtNum* jacp = mj_stackAlloc(d, 3 * nv);
  mjtNum* jacr = mj_stackAlloc(d, 3 * nv);
  mj_jacSite(m, d, jacp, jacr, arm.site_id());
  for (int i = 0; i < kNumJoints; ++i) {
    const int c = arm.dof_address(i);
    for (int r = 0; r < 3; ++r) {
      jacobian(r, i) = jacp[r * nv + c];
      jacobian(r + 3, i) = jacr[r * nv + c];
    }
  }
  mjFREESTACK;
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
