#pragma once
/// Inverse kinematics of the club face: damped least squares on position + orientation with a
/// posture task in the null space, joint-limit aware (joints that would cross a position or
/// velocity bound are clamped and taken out of the task, then the rest is re-solved).
///
/// Face task: the `club_face` frame (x = face normal, z = up along the face) should equal
/// R_z(heading) at a given position, i.e. the face is vertical and its normal points along the
/// horizontal hitting direction `heading`.
#include "robot/arm_model.hpp"

namespace mg::robot {

/// Gains and bounds of the velocity-level IK (one control period).
struct IkOptions {
  double damping = 0.02;           ///< DLS lambda (task units m/rad)
  double position_gain = 20.0;     ///< [1/s] feedback on the face position error
  double orientation_gain = 20.0;  ///< [1/s] feedback on the face orientation error
  double posture_gain = 2.0;       ///< [1/s] null-space pull towards the posture
  double limit_margin = 0.05;      ///< [rad] joints stay this far inside their position limits
  double dt = 0.002;            ///< [s] period: bounds qd so that q + qd dt stays inside the margin
  double velocity_scale = 1.0;  ///< fraction of the joint velocity limits allowed, (0, 1]

  /// Throws mg::InputError naming the field.
  void validate() const;
};

/// Desired club-face state, world frame.
struct FaceTarget {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< [m] face centre
  double heading = 0.0;                ///< [rad] face-normal direction about world z
  Vector6 velocity = Vector6::Zero();  ///< [m/s, rad/s] feed-forward twist (linear; angular)
};

/// R_z(heading): the face orientation for a hitting direction [rad].
Eigen::Matrix3d face_rotation(double heading);

/// [m; rad] (6) task error: desired - current position, and the rotation vector of
/// R_desired R_current^T (world frame).
Vector6 face_pose_error(const Eigen::Isometry3d& current, const Eigen::Vector3d& position,
                        const Eigen::Matrix3d& rotation);

/// Real-time velocity IK: joint velocities qd [rad/s] (7) with J qd ~= task_velocity [m/s; rad/s]
/// (6, world) plus (I - J^+ J) posture_velocity [rad/s] (7), within the joint velocity limits and
/// so that q + qd dt stays inside the position limits less the margin. `jacobian` is the club-face
/// Jacobian at q (rows linear; angular). Returns kSaturated if a bound was active, kInvalidInput
/// (qd = 0) on non-finite input. No allocation, no throw.
[[nodiscard]] RtStatus velocity_ik(const ArmModel& arm, const Vector7& q, const Matrix67& jacobian,
                                   const Vector6& task_velocity, const Vector7& posture_velocity,
                                   const IkOptions& options, Vector7& qd);

/// Real-time closed-loop face tracking: task velocity = target.velocity + gains * pose error,
/// posture velocity = posture_gain (posture - q), pose and Jacobian from the DH model; then
/// velocity_ik. Writes the pose error [m; rad] into `error` if given. No allocation, no throw.
[[nodiscard]] RtStatus track_face(const ArmModel& arm, const Vector7& q, const FaceTarget& target,
                                  const Vector7& posture, const IkOptions& options, Vector7& qd,
                                  Vector6* error = nullptr);

/// Options of the position-level solver.
struct IkSolveOptions {
  int max_iterations = 3000;
  double position_tolerance = 1e-4;     ///< [m]
  double orientation_tolerance = 1e-3;  ///< [rad]
  /// Per-iteration IK: a 10 ms step with gains of 50 /s (half the error per step) and a stronger
  /// posture pull than the 500 Hz controller.
  IkOptions step{.damping = 0.02,
                 .position_gain = 50.0,
                 .orientation_gain = 50.0,
                 .posture_gain = 5.0,
                 .limit_margin = 0.05,
                 .dt = 0.01,
                 .velocity_scale = 1.0};

  void validate() const;
};

struct IkResult {
  Vector7 q = Vector7::Zero();  ///< [rad] final joint positions (always within limits)
  bool converged = false;
  int iterations = 0;
  double position_error = 0.0;     ///< [m]
  double orientation_error = 0.0;  ///< [rad]
};

/// Position-level IK (not real-time): integrates track_face from `start` until the face pose is
/// within tolerance. `posture` [rad] (7) resolves the redundancy; if the descent from `start`
/// stalls (half the iteration budget), it restarts once from `posture`. Throws mg::InputError on
/// non-finite input or a start outside the joint limits.
IkResult solve_ik(const ArmModel& arm, const FaceTarget& target, const Vector7& start,
                  const Vector7& posture, const IkSolveOptions& options = {});

}  // namespace mg::robot
