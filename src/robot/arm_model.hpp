#pragma once
/// The immutable arm description used by kinematics, dynamics and IK, and helpers that read
/// the club pose and Jacobian out of a MuJoCo simulation.
#include <mujoco/mujoco.h>

#include <array>

#include "robot/kinematics.hpp"
#include "robot/wam_model.hpp"

namespace mg::robot {

/// Outcome of a real-time function (which never throws).
enum class RtStatus {
  kOk,            ///< result valid
  kSaturated,     ///< result valid but clipped by a joint position/velocity limit
  kInvalidInput,  ///< an input was NaN/inf; outputs are set to zero
};

/// Validated, immutable arm model: mount transform, club, limits, dynamic parameters and (when
/// built from an mjModel) the MuJoCo addresses of the 7 joints, the flange body and the face site.
/// Cheap to copy; holds no pointer into the mjModel.
class ArmModel {
 public:
  /// Model for pure computations (DH kinematics, RNEA, IK) with no MuJoCo indices.
  explicit ArmModel(const WamMount& mount);

  /// Looks up `wam_j1..7`, `wam_link7`, `club_face`, `wam_m1..7` in `m` and reads position and
  /// torque limits from it. Throws mg::InputError if a name is missing or if the compiled
  /// shoulder frame does not match `mount` (so DH and MuJoCo routes agree).
  ArmModel(const mjModel* m, const WamMount& mount);

  const WamMount& mount() const { return mount_; }
  bool has_mujoco() const { return site_id_ >= 0; }

  /// world_T_0: DH frame 0 (shoulder) in the world.
  const Eigen::Isometry3d& shoulder_in_world() const { return world_from_shoulder_; }
  /// 7_T_face: the club_face frame in the flange (DH frame 7).
  const Eigen::Isometry3d& face_in_flange() const { return flange_from_face_; }

  int qpos_address(int joint) const {
    return qpos_adr_[static_cast<std::size_t>(joint)];
  }  ///< joint 0..6
  int dof_address(int joint) const {
    return dof_adr_[static_cast<std::size_t>(joint)];
  }  ///< joint 0..6
  int actuator_id(int joint) const {
    return actuator_id_[static_cast<std::size_t>(joint)];
  }  ///< joint 0..6
  int site_id() const { return site_id_; }
  int flange_body_id() const { return flange_body_; }

  const Vector7& position_lower() const { return lower_; }       ///< [rad] (7)
  const Vector7& position_upper() const { return upper_; }       ///< [rad] (7)
  const Vector7& velocity_limit() const { return vel_limit_; }   ///< [rad/s] (7)
  const Vector7& torque_limit() const { return torque_limit_; }  ///< [N m] (7)
  const Vector7& armature() const { return armature_; }          ///< [kg m^2] (7)
  const Vector7& damping() const { return damping_; }            ///< [N m s/rad] (7)
  /// Link inertials in their DH frames; entry 6 is link 7 with the club rigidly attached.
  const std::array<LinkInertial, kNumJoints>& inertials() const { return inertials_; }
  /// [m/s^2] gravity in frame 0, (3).
  const Eigen::Vector3d& gravity() const { return gravity_; }

 private:
  WamMount mount_;
  Eigen::Isometry3d world_from_shoulder_;
  Eigen::Isometry3d flange_from_face_;
  std::array<int, kNumJoints> qpos_adr_{-1, -1, -1, -1, -1, -1, -1};
  std::array<int, kNumJoints> dof_adr_{-1, -1, -1, -1, -1, -1, -1};
  std::array<int, kNumJoints> actuator_id_{-1, -1, -1, -1, -1, -1, -1};
  int site_id_ = -1;
  int flange_body_ = -1;
  Vector7 lower_, upper_, vel_limit_, torque_limit_, armature_, damping_;
  std::array<LinkInertial, kNumJoints> inertials_;
  Eigen::Vector3d gravity_;
};

// ---- MuJoCo route (all real-time safe: no allocation, no throw; need a MuJoCo-built ArmModel) --

/// [rad] arm joint positions from d->qpos, (7).
Vector7 joint_positions(const ArmModel& arm, const mjData* d);
/// [rad/s] arm joint velocities from d->qvel, (7).
Vector7 joint_velocities(const ArmModel& arm, const mjData* d);
/// Writes the arm joint positions into d->qpos (other entries untouched).
void set_joint_positions(const ArmModel& arm, mjData* d, const Vector7& q);

/// world_T_face from d->site_xpos/site_xmat (valid after mj_kinematics or mj_forward).
Eigen::Isometry3d club_pose(const ArmModel& arm, const mjData* d);
/// world_T_7: the flange (link-7 body) frame from d->xpos/xmat.
Eigen::Isometry3d flange_pose(const ArmModel& arm, const mjData* d);

/// Club-face Jacobian via mj_jacSite, world frame: rows 0-2 linear [m/rad], rows 3-5 angular
/// [rad/rad], columns = arm joints. Needs mj_kinematics + mj_comPos (or mj_forward) on `d`;
/// scratch memory comes from the mjData stack.
void club_jacobian(const ArmModel& arm, const mjModel* m, mjData* d, Matrix67& jacobian);

// ---- DH route (independent of MuJoCo; real-time safe) ----

/// world_T_7 from the DH table.
Eigen::Isometry3d dh_flange_pose(const ArmModel& arm, const Vector7& q);
/// world_T_face from the DH table.
Eigen::Isometry3d dh_club_pose(const ArmModel& arm, const Vector7& q);
/// Club-face pose and geometric Jacobian (same layout as club_jacobian) from the DH table.
void dh_club_jacobian(const ArmModel& arm, const Vector7& q, Eigen::Isometry3d& pose,
                      Matrix67& jacobian);

}  // namespace mg::robot
