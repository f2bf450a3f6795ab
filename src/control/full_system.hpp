#pragma once
/// The module in fast (lockstep) simulator mode: one thread steps the physics (1 ms, World::step),
/// calls the core update every 2 steps (500 Hz) and, inside it, the robot update every 5th core
/// tick; user requests are made between ticks. Deterministic: the same world, inputs and config
/// give the same bits (wall-clock timing is measured but never fed back).
#include <array>
#include <cstdint>
#include <vector>

#include "control/minigolf_module.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"

namespace mg::control {

/// The field's world with the WAM + club inserted (default mount).
sim::World make_world_with_arm(field::Field field, const robot::WamMount& mount = {},
                               sim::WorldOptions options = {});

/// The module model for a world built by make_world_with_arm with the same mount.
ModuleModel make_module_model(const sim::World& world, ds::HittingModel hitting,
                              const ModuleConfig& config, const robot::WamMount& mount = {});

/// Wall-clock timing of the core updates of a run.
struct CoreTiming {
  double core_update_p99_us = 0.0;
  double core_update_max_us = 0.0;
  double core_update_mean_us = 0.0;
  int overruns = 0;  ///< core updates that took longer than the core period
  int ticks = 0;
};

/// One thread, lockstep: physics and module on the same clock.
class LockstepRunner {
 public:
  /// Perception defaults to the simulator's ground truth (simulator mode).
  LockstepRunner(const sim::World& world, const ModuleModel& model, mjData* d);
  /// Uses `perception` (not owned; must outlive the runner) for the robot update, e.g. the
  /// network feed in normal mode; its clock is the simulated time d->time. nullptr: ground truth.
  void set_perception(perception::Perception* perception);
  /// One physics step; before it, on a core tick, the robot update (every robot_update_divider-th
  /// tick, with the perception at d->time) and the core update. Records the core update's wall
  /// time.
  void step();
  /// Resets the module to Idle at the current arm state of d and clears timing.
  void reset_module();
  ModuleData& module() { return data_; }
  const ModuleData& module() const { return data_; }
  long steps() const { return steps_; }
  CoreTiming timing() const;

 private:
  const sim::World* world_;
  const ModuleModel* model_;
  mjData* d_;
  ModuleData data_;
  perception::SimulatorPerception truth_;
  perception::Perception* perception_;
  int steps_per_tick_ = 2;
  long steps_ = 0;
  std::vector<float> durations_us_;  // reserved up front; grows only past the reservation
};

struct FullPuttOptions {
  double settle_timeout = 6.0;    ///< [s] to reach the rest pose
  double hit_timeout = 3.0;       ///< [s] from the hit request to contact
  double max_duration = 30.0;     ///< [s] ball roll after the hit
  double launch_delay = 0.02;     ///< [s] after the first contact, when the launch is measured
  sim::OutcomeRules rules{};

  // --- Execution noise (launch study, thesis 6.1). Zero noise: the run is unchanged, bit for bit.
  /// Std of a Gaussian joint-torque disturbance, as a fraction of each joint's torque limit; a
  /// fresh draw per joint every core tick, added to the plant (d->qfrc_applied at the arm's dofs,
  /// after the controller's clamp) for the whole run (rest, hit, roll). [-]
  double torque_noise = 0.0;
  /// Std of the ball's placement error around the tee, per horizontal axis. [m]
  double placement_noise = 0.0;
  /// Seed of the noise (mg::Rng; placement and torque use derive_seed(seed, 0) and (seed, 1)).
  std::uint64_t seed = 0;
};

/// Angle [rad] (atan2 of the horizontal components) and speed [m/s] of a velocity.
struct AngleSpeed {
  double angle = 0.0;
  double speed = 0.0;
};

struct FullPuttResult {
  bool hit = false;                 ///< the club struck the ball
  std::array<double, 2> ball_start{0.0, 0.0};  ///< [m] where the ball was placed (tee + noise)
  bool hit_refused = false;         ///< the module refused the request (envelope, NaN)
  sim::PuttOutcome outcome;  ///< the ball's outcome; duration [s] and steps count from first contact
  AngleSpeed club;  ///< club face velocity just before first contact (speed: 3-D norm)
  AngleSpeed launch;                ///< ball velocity launch_delay after contact (horizontal)
  CoreTiming timing;
  double max_torque_ratio = 0.0;    ///< max |tau_j| / limit_j of the applied torques
  double max_raw_torque_ratio = 0.0;  ///< the same before the clamp
  double max_velocity_ratio = 0.0;  ///< max |qd_j| / limit_j measured
  double max_command_velocity_ratio = 0.0;  ///< max |qd_des_j| / limit_j commanded by the module
  double min_position_margin = 0.0;  ///< [rad] min distance of a joint to its range ends
  double rest_time = 0.0;           ///< [s] simulated time to reach the rest pose
  double hit_time = 0.0;            ///< [s] from the hit request to contact
  bool faulted = false;             ///< a fault was observed during the run
  /// Separate club-ball contacts over the run (1: the ball was touched once, as it should be).
  int club_ball_touches = 0;
  bool touching_ball = false;  ///< (bookkeeping of the count: in contact at the last step)
};

/// Resets `d`, sets the hole, puts the arm at the default rest posture, goes to the rest pose for
/// `angle`, hits at `speed` and simulates until the ball's outcome is decided. Deterministic.
/// Throws InputError for a bad hole; a refused request is reported in the result.
FullPuttResult full_system_putt(const sim::World& world, const ModuleModel& model, mjData* d,
                                std::array<double, 2> hole, double angle, double speed,
                                const FullPuttOptions& options = {});

}  // namespace mg::control
