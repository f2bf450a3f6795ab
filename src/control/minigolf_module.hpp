#pragma once
/// The minigolf module (thesis chapter 4): the 500 Hz core update that turns the state machine
/// (module_state.hpp), the hitting DS and the arm model into joint torques.
///
/// Model/Data split: `ModuleModel` is immutable after construction (config, arm, hitting model);
/// `ModuleData` is the mutable, preallocated per-run state. One Data per thread.
///
/// The core tick is read -> update -> write (control/arm_interface.hpp): `module_update` takes the
/// measured joint state and returns joint torques and a status; an ArmBackend (the simulator,
/// sim_backend/mujoco_arm.hpp; a fake in tests; a driver for the real WAM, docs/hardware.md) does
/// the read and the write, `control_tick` does all three. Nothing here knows the simulator: no
/// MuJoCo header, id or mjData (the adapter, sim_backend/mujoco_arm.hpp, builds the model from a
/// simulation and resets the module from one). The one scheduler, sim_backend/core_loop.hpp, calls
/// `robot_update` every `robot_update_divider`-th core tick with the perception of that moment,
/// then the core tick; the module code is the same for putts, the console and the viewer.
///
/// Hit detection, from measurements only: the ball is hit once the club head (FK of the measured
/// joints, the head's box) reaches the perceived ball, or once the perceived ball has moved more
/// than ball_moved_distance since the hit began. (The simulator's contact list is a cross-check
/// in tests: FullPuttResult::hit_detection_lag.)
///
/// Real-time contract: `module_update`, `control_tick` and `robot_update` allocate nothing and
/// never throw; a NaN, a limit breach or a failed DS/IK evaluation becomes a fault observation,
/// and next_state brakes. `request_hit`, `request_rest`, `request_idle` are the user update:
/// called between ticks, they may validate and fail (the hit request is refused, never thrown).
///
/// Control law (per core tick of period T = 2 ms):
///   Idle    tau = g(q) (gravity compensation; the reference follows the measurement)
///   Rest    a set-point moves toward the rest face pose (speed- and turn-rate-limited); IK
///   Hitting the DS (robot update, every 5th tick) gives the velocity of the point p = face centre
///           + offset psi; its reference p_ref is integrated every tick; IK with feed-forward
///   Braking the reference face velocity ramps to zero over brake_time while the club is lifted
/// IK = track_face on the reference joint positions q_ref -> qd_ik, FIR low-pass -> qd_des,
/// q_ref += qd_des T, qdd_des = (qd_des - qd_des_prev) / T, then computed-torque PID:
///   tau = RNEA(q, qd, qdd_des + kp (q_ref - q) + ki int(q_ref - q) + kd (qd_des - qd)),
/// clamped to the torque limits.
#include <array>
#include <cstdint>

#include "control/arm_interface.hpp"
#include "control/module_config.hpp"
#include "control/module_state.hpp"
#include "ds/hitting_ds.hpp"
#include "ds/hitting_model.hpp"
#include "perception/perception.hpp"
#include "robot/arm_model.hpp"
#include "robot/ik.hpp"

namespace mg::control {

/// Moving-average FIR filter over joint vectors; fixed capacity, no allocation.
struct FirFilter {
  static constexpr int kMaxTaps = 32;
  std::array<robot::Vector7, kMaxTaps> buffer{};
  robot::Vector7 sum = robot::Vector7::Zero();
  int taps = 1;
  int head = 0;
};
/// Fills the filter history with `value` (a step-free start). Real-time safe.
void fir_reset(FirFilter& f, int taps, const robot::Vector7& value);
/// Pushes `input`, returns the mean of the last `taps` inputs. Real-time safe.
robot::Vector7 fir_step(FirFilter& f, const robot::Vector7& input);

/// Immutable part of the module.
class ModuleModel {
 public:
  /// The arm, the hitting model, the config and the ball's radius [m] (hit detection); in the
  /// simulator control::make_module_model (sim_backend/mujoco_arm.hpp) reads the arm and the radius
  /// from the compiled world. Validates; throws mg::InputError.
  ModuleModel(robot::ArmModel arm, ds::HittingModel hitting, const ControllerConfig& config,
              double ball_radius);

  const ControllerConfig& config() const { return config_; }
  const robot::ArmModel& arm() const { return arm_; }
  const ds::HittingModel& hitting() const { return hitting_; }
  const robot::IkOptions& ik() const { return ik_; }
  double ball_radius() const { return ball_radius_; }  ///< [m]
  /// [m/s] club speed cap of this mode (speed_max, or kSafeEndpointSpeed in normal mode).
  double speed_cap() const { return speed_cap_; }
  /// [m/s] the most the DS velocity may ask of the club at any angle (arm_speed_cap, and the
  /// mode's cap).
  double club_speed_cap() const { return dynamic_cap_; }
  /// [m/s] the same for hitting angle `angle` [rad] (lower for negative angles).
  double club_speed_cap(double angle) const;
  const robot::Vector7& posture() const { return posture_; }  ///< [rad] null-space posture (7)
  /// [m/s], [rad/s] rest set-point speed and turn rate of this mode (halved in normal mode).
  double rest_speed() const { return rest_speed_; }
  double rest_turn_rate() const { return rest_turn_rate_; }

 private:
  ControllerConfig config_;
  robot::ArmModel arm_;
  ds::HittingModel hitting_;
  robot::IkOptions ik_;
  robot::Vector7 posture_;
  double ball_radius_ = 0.0;
  double speed_cap_ = 3.0;
  double dynamic_cap_ = 3.0;
  double rest_speed_ = 0.25;
  double rest_turn_rate_ = 0.8;
};

/// Mutable per-run state of the module. Construct with the model (allocates the DS scratch once).
class ModuleData {
 public:
  explicit ModuleData(const ModuleModel& model);

  ModuleState state = ModuleState::kIdle;
  Command pending = Command::kNone;  ///< user command for the next tick
  bool request_valid = false;
  double angle = 0.0;  ///< [rad] commanded hitting angle theta
  double speed = 0.0;  ///< [m/s] commanded club speed at the ball
  ds::HittingDsData ds;

  std::int64_t tick = 0;                             ///< core ticks since reset
  double time_in_state = 0.0;                        ///< [s]
  robot::Vector7 q_ref = robot::Vector7::Zero();     ///< [rad] reference joint positions (7)
  robot::Vector7 qd_des = robot::Vector7::Zero();    ///< [rad/s] filtered desired velocities
  robot::Vector7 qdd_des = robot::Vector7::Zero();   ///< [rad/s^2]
  robot::Vector7 integral = robot::Vector7::Zero();  ///< [rad s] PID integral
  robot::Vector7 tau = robot::Vector7::Zero();       ///< [N m] last command (after the clamp)
  robot::Vector7 tau_raw = robot::Vector7::Zero();   ///< [N m] before the clamp
  FirFilter fir;

  Eigen::Vector3d setpoint = Eigen::Vector3d::Zero();  ///< [m, world] face set-point (Rest/Braking)
  double setpoint_heading = 0.0;                       ///< [rad]
  Eigen::Vector3d p_ref = Eigen::Vector3d::Zero();     ///< [m, world] DS point reference (Hitting)
  Eigen::Vector3d v_ds = Eigen::Vector3d::Zero();   ///< [m/s, world] last robot-update DS velocity
  Eigen::Vector3d v_ref = Eigen::Vector3d::Zero();  ///< [m/s, world] ramped DS velocity (Hitting)
  Eigen::Vector3d v_brake0 = Eigen::Vector3d::Zero();  ///< [m/s] face reference velocity at braking
  bool at_rest_pose = false;
  bool ball_hit = false;                          ///< latched during a hit
  HitEvidence hit_evidence = HitEvidence::kNone;  ///< what showed it
  /// [m, world] the perceived ball when the hit began (ball motion is measured from there).
  std::array<double, 3> ball_at_hit_start{0, 0, 0};
  std::int64_t hit_start_tick = 0;  ///< core tick the hit began
  bool compute_fault = false;       ///< IK/RNEA failed last tick: reported as a fault this tick
  /// Set by a real-time scheduler after an overrun streak; a fault until the module is reset.
  bool overrun_fault = false;
  /// Set by the core loop when a hook threw (sim_backend/core_loop.hpp); a fault until reset.
  bool hook_fault = false;
  perception::Perceived seen;   ///< last perception handed to the robot update
  std::int64_t seen_tick = -1;  ///< core tick of the last fresh perception (-1: never)
  TickInfo last;
};

/// Resets the data to Idle with the reference at the measured joint positions `q` [rad] (in a
/// simulation: control::module_reset of sim_backend/mujoco_arm.hpp).
void module_reset(const ModuleModel& model, ModuleData& data, const robot::Vector7& q);

/// User update (not real-time): ask for the rest pose for hitting angle `angle` [rad].
/// Returns false (and changes nothing) if the angle is outside the envelope or not finite.
bool request_rest(const ModuleModel& model, ModuleData& data, double angle);
/// User update: ask for a hit at `angle` [rad], club speed `speed` [m/s]. A request outside the
/// envelope (or NaN) is recorded as invalid: next_state refuses it. Returns the validity.
bool request_hit(const ModuleModel& model, ModuleData& data, double angle, double speed);
void request_idle(ModuleData& data);

/// The 500 Hz core update: from the measured joint state (and the latest perception: the robot
/// update's, or `measured.perception`, which runs robot_update first) runs the state machine and
/// computes the joint torques.
/// Real-time safe: no allocation, no throw; any input (NaN, out of range) gives a finite,
/// clamped command (a fault brakes).
ModuleCommand module_update(const ModuleModel& model, ModuleData& data,
                            const MeasuredState& measured) noexcept;

/// One core tick on an arm: backend.read() -> module_update -> backend.write(). Real-time safe
/// when the backend is.
ModuleCommand control_tick(const ModuleModel& model, ModuleData& data,
                           ArmBackend& backend) noexcept;

/// The robot update (every robot_update_divider-th core tick, called by the scheduler): takes the
/// perceived ball and hole and, while hitting, evaluates the DS velocity at p_ref. Real-time safe.
void robot_update(const ModuleModel& model, ModuleData& data,
                  const perception::Perceived& seen) noexcept;

/// True if the club head (its box, at face pose `face` [world]: x the face normal, y heel, z up)
/// touches or has passed through a ball of the model's radius centred at `ball` [m, world].
bool club_reaches_ball(const ModuleModel& model, const Eigen::Isometry3d& face,
                       const std::array<double, 3>& ball) noexcept;

/// True while the last fresh perception is at most perception_max_age old (in core ticks).
bool perception_fresh(const ModuleModel& model, const ModuleData& data);
/// True if the perceived ball lies within ball_tolerance (horizontally) of the hitting point x*.
bool ball_in_place(const ModuleModel& model, const ModuleData& data);

/// [m, world] the club face rest position and [rad] heading for hitting angle `angle`.
Eigen::Vector3d rest_face_position(const ModuleModel& model, double angle);

}  // namespace mg::control
