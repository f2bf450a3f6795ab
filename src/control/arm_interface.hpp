#pragma once
/// The control boundary between the minigolf module and an arm (libfranka / ros2_control style):
/// every 500 Hz core tick is read -> update -> write.
///
///   MeasuredState s = backend.read();            // the driver: encoders, clock (+ perception)
///   ModuleCommand c = module_update(model, data, s);  // the module: no simulator access
///   backend.write(c);                            // the driver: joint torques to the motors
///
/// The module sees only what a real system measures: joint positions and velocities, the sample
/// time and what perception reports. The simulator is one backend (sim_backend/mujoco_arm.hpp); a
/// driver for the real WAM is another (docs/hardware.md says what it must do). Both `read` and
/// `write` run inside the real-time tick: no allocation, no throw, bounded time.
#include <optional>

#include "control/module_state.hpp"
#include "perception/perception.hpp"
#include "robot/arm_model.hpp"
#include "robot/kinematics.hpp"

namespace mg::control {

/// What the arm's driver measured at one core tick.
struct MeasuredState {
  double time = 0.0;                           ///< [s] sample time, the driver's monotonic clock
  robot::Vector7 q = robot::Vector7::Zero();   ///< [rad] joint positions (encoders), J1..J7
  robot::Vector7 qd = robot::Vector7::Zero();  ///< [rad/s] joint velocities, J1..J7
  /// What perception sees, on robot-update ticks (every robot_update_divider-th): module_update
  /// then runs the robot update (robot_update: the perception and the DS) first. Empty on the
  /// other ticks, and for schedulers that call robot_update themselves (control::CoreLoop); the
  /// module acts on the latest perception either way.
  std::optional<perception::Perceived> perception;
};

/// How the module knows the ball was hit (from measurements only).
enum class HitEvidence {
  kNone,
  kClubPath,    ///< the club head, by FK of the measured joints, reached the perceived ball
  kBallMotion,  ///< the perceived ball moved more than ball_moved_distance since the hit began
};

/// Statistics of one core tick (the status half of ModuleCommand; also kept in ModuleData::last).
struct TickInfo {
  Reason reason = Reason::kNoChange;
  robot::RtStatus ik_status = robot::RtStatus::kOk;
  bool torque_clamped = false;  ///< a joint's demand exceeded its limit (the command is clamped)
  bool fault = false;
  HitEvidence hit = HitEvidence::kNone;  ///< what first showed the ball hit (latched for the hit)
};

/// What the module asks of the arm for the next core period.
struct ModuleCommand {
  /// [N m] joint torques J1..J7 to hold until the next write: always finite and within the
  /// arm's torque limits (zero when the measurement was unusable: the driver's brakes take over).
  robot::Vector7 tau = robot::Vector7::Zero();
  ModuleState state = ModuleState::kIdle;  ///< the module's state after this tick
  TickInfo status;
};

/// An arm the module can drive: the simulator, a fake in tests, or a driver for the real WAM.
class ArmBackend {
 public:
  virtual ~ArmBackend() = default;
  /// The joint state now. Real-time: no allocation, no throw, bounded time.
  virtual MeasuredState read() noexcept = 0;
  /// Applies `command.tau` until the next write. Real-time: no allocation, no throw.
  virtual void write(const ModuleCommand& command) noexcept = 0;
};

}  // namespace mg::control
