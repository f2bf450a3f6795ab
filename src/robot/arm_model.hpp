#pragma once
/// The immutable arm description used by kinematics, dynamics and IK (the DH route). No
/// simulator: a model built from a compiled MuJoCo model, the MuJoCo addresses of the arm and the
/// functions that read a simulation are in sim_backend/arm_mujoco.hpp.
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

/// Joint parameters that a compiled model (or a calibration) may give instead of the published
/// tables (wam_params.hpp).
struct JointParameters {
  Vector7 lower;                                   ///< [rad] position limits (7)
  Vector7 upper;                                   ///< [rad]
  Vector7 armature;                                ///< [kg m^2]
  Vector7 damping;                                 ///< [N m s/rad]
  Vector7 torque_limit;                            ///< [N m]
  Eigen::Vector3d gravity_world{0.0, 0.0, -9.81};  ///< [m/s^2] world frame
};

/// Validated, immutable arm model: mount transform, club, limits, dynamic parameters. Cheap to
/// copy; knows nothing of a simulator.
class ArmModel {
 public:
  /// The published tables' parameters (wam_params.hpp).
  explicit ArmModel(const WamMount& mount);
  /// The same with these joint parameters (robot::arm_model_from_mujoco reads them from a
  /// compiled model).
  ArmModel(const WamMount& mount, const JointParameters& joints);

  const WamMount& mount() const { return mount_; }

  /// world_T_0: DH frame 0 (shoulder) in the world.
  const Eigen::Isometry3d& shoulder_in_world() const { return world_from_shoulder_; }
  /// 7_T_face: the club_face frame in the flange (DH frame 7).
  const Eigen::Isometry3d& face_in_flange() const { return flange_from_face_; }

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
  Vector7 lower_, upper_, vel_limit_, torque_limit_, armature_, damping_;
  std::array<LinkInertial, kNumJoints> inertials_;
  Eigen::Vector3d gravity_;
};

// ---- DH route (independent of MuJoCo; real-time safe) ----

/// world_T_7 from the DH table.
Eigen::Isometry3d dh_flange_pose(const ArmModel& arm, const Vector7& q);
/// world_T_face from the DH table.
Eigen::Isometry3d dh_club_pose(const ArmModel& arm, const Vector7& q);
/// Club-face pose and geometric Jacobian (same layout as club_jacobian) from the DH table.
void dh_club_jacobian(const ArmModel& arm, const Vector7& q, Eigen::Isometry3d& pose,
                      Matrix67& jacobian);

}  // namespace mg::robot
