#pragma once
/// Our own rigid-body dynamics of the WAM + club (recursive Newton-Euler over the DH frames),
/// independent of MuJoCo. All functions are real-time safe: no allocation, no throw.
#include "robot/arm_model.hpp"

namespace mg::robot {

/// Which joint-space terms besides the rigid-body ones to include.
struct DynamicsTerms {
  bool armature = true;  ///< + armature .* qdd (reflected rotor inertia)
  bool damping = true;   ///< + damping .* qd (viscous joint friction)
  bool gravity = true;   ///< gravity of arm.gravity()
};

/// tau = M(q) qdd + c(q, qd) + g(q) [+ armature qdd + damping qd]: the joint torques [N m] (7)
/// that produce accelerations qdd [rad/s^2] at positions q [rad] and velocities qd [rad/s].
/// Matches MuJoCo's qfrc_inverse for the generated model (armature in M, damping as passive force).
/// Returns kInvalidInput (tau = 0) if any input is not finite.
[[nodiscard]] RtStatus inverse_dynamics(const ArmModel& arm, const Vector7& q, const Vector7& qd,
                                        const Vector7& qdd, Vector7& tau,
                                        const DynamicsTerms& terms = {});

/// Gravity torques g(q) [N m] (7).
[[nodiscard]] RtStatus gravity_torque(const ArmModel& arm, const Vector7& q, Vector7& tau);

/// Joint-space inertia M(q) [kg m^2] (7x7), including armature when terms.armature, column by
/// column from the RNEA (7 passes).
[[nodiscard]] RtStatus mass_matrix(const ArmModel& arm, const Vector7& q, Matrix7& mass,
                                   bool with_armature = true);

}  // namespace mg::robot
