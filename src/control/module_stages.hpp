#pragma once
/// The stages of the module's core update, in the order module_update runs them:
///
///   observe     the measurement (and the perception it carries) -> Observation: faults, the hit
///   transition  next_state on the observation; a new state starts its reference afresh
///   reference   the club face's target of this tick: the rest set-point, the DS point, braking
///   track       velocity IK to the target from q_ref, FIR low-pass, q_ref integrated
///   torque      computed-torque PID through the RNEA (gravity in Idle), clamped to the limits
///
/// In Idle, or with an unusable measurement, `hold` stands in for reference and track: the
/// tracking state is zeroed and the reference follows the measurement (set by `transition`).
///
/// Each stage is a free function over the module's model (read only) and data (the fields it
/// names); module_update is their composition and the only caller in the library. They are
/// separate so that each can be read and tested alone. Real-time: no allocation, no throw.
#include "control/minigolf_module.hpp"
#include "robot/ik.hpp"

namespace mg::control {

/// Runs the robot update first if `measured.perception` is set, consumes the pending user
/// command, and returns what next_state decides on: a fault (unusable or out-of-limit
/// measurement, a compute fault of the last tick, a latched overrun or hook fault, a hit that
/// takes too long or lost its ball), the rest pose reached, the joints stationary, and while
/// hitting the hit (latched in data.ball_hit with its evidence) or the ball passed.
Observation observe(const ModuleModel& model, ModuleData& data,
                    const MeasuredState& measured) noexcept;

/// Applies next_state: on a change, the new state's reference starts from FK of q_ref (rest
/// set-point, DS point, braking velocity). In Idle, or with a non-finite q_ref, q_ref is set to
/// the measured `q` [rad] (zero if that is not finite). Returns the transition's reason.
Reason transition(const ModuleModel& model, ModuleData& data, const Observation& observation,
                  const robot::Vector7& q) noexcept;

/// The club face's target [m, rad, m/s; world] for this tick in Rest, Hitting or Braking (the
/// default target in Idle): advances the set-point (Rest, Braking) or the DS point p_ref
/// (Hitting), and in Rest sets data.at_rest_pose from the measured face. Needs a finite
/// measurement.
robot::FaceTarget reference(const ModuleModel& model, ModuleData& data,
                            const MeasuredState& measured) noexcept;

/// Velocity IK from q_ref to `target` (zero velocity if the IK reports invalid input), the FIR
/// low-pass into qd_des [rad/s], qdd_des [rad/s^2] by difference, q_ref += qd_des T. Returns the
/// IK's status.
robot::RtStatus track(const ModuleModel& model, ModuleData& data,
                      const robot::FaceTarget& target) noexcept;

/// Instead of reference and track in Idle or with an unusable measurement: qd_des and qdd_des
/// zero; in Idle with a usable measurement also the FIR history and the PID integral.
void hold(const ModuleModel& model, ModuleData& data, const MeasuredState& measured) noexcept;

/// The torque stage's result.
struct TorqueOutput {
  robot::Vector7 tau = robot::Vector7::Zero();  ///< [N m] finite, within the torque limits
  bool clamped = false;                         ///< a joint's demand exceeded its limit
  bool failed = false;  ///< the RNEA failed (gravity compensation was used instead): a fault
};

/// Joint torques for this tick: zero with an unusable measurement, gravity compensation in Idle,
/// else tau = RNEA(q, qd, qdd_des + kp e + ki int(e) + kd (qd_des - qd)), e = q_ref - q (the
/// integral in data, clamped to integral_limit). Sets data.tau_raw and data.tau (clamped).
TorqueOutput torque(const ModuleModel& model, ModuleData& data,
                    const MeasuredState& measured) noexcept;

}  // namespace mg::control
