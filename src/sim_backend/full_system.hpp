#pragma once
/// Full-system putts: the module in fast (lockstep) simulator mode on the core loop
/// (sim_backend/core_loop.hpp: physics in 1 ms steps, the core update every 2 steps, the robot
/// update every 5th core tick), user requests between ticks. Deterministic: the same world, inputs
/// and config give the same bits (wall-clock timing is measured but never fed back).
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "control/minigolf_module.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"
#include "sim_backend/core_loop.hpp"
#include "sim_backend/mujoco_arm.hpp"
#include "sim_backend/plant_effects.hpp"

namespace mg::control {

/// How a full-system putt brings the arm to the rest pose of its angle before the hit.
enum class RestStart {
  /// From robot::kDefaultRestPosture, the module's Rest motion to the rest pose (0.76-1.65 s
  /// simulated), as on the real arm. The ball sits on its start meanwhile.
  kApproach,
  /// The same approach with a plant that follows the module's reference exactly and is not
  /// simulated (the module's reference in Rest does not depend on the measurement), the ball
  /// settled on its start; physics from the hit request on. The arm starts the hit where the
  /// simulated approach leaves it, up to its tracking error (notes/speed.md). With an arm that is
  /// not ideal (PlantEffects::ideal_arm: torque noise) the approach is simulated (kApproach).
  kKinematicApproach,
  /// The arm starts still at the rest pose (the module's IK fixed point for it), the ball settled
  /// on its start; after kAtRestSettleTime in Rest the hit is asked for. Cheapest, but the arm's
  /// null-space posture is not the approach's, and with it the club's effective mass at impact:
  /// launch speeds differ by 2 % typically (notes/speed.md).
  kAtRestPose,
};

/// [s] time in Rest before the hit with RestStart::kAtRestPose (10 core ticks).
inline constexpr double kAtRestSettleTime = 0.02;

/// The harness's settings of a full-system putt: how it starts, its time limits, what it records,
/// the rules, the ball world, the ball's placement, the perception source and the stance. The
/// true world's effects on the arm, the hit, the launch and the vision are wrappers the caller
/// hands over apart (sim_backend/plant_effects.hpp).
struct FullPuttOptions {
  RestStart rest_start = RestStart::kApproach;
  /// Not owned, may be shared by threads; must outlive the call. A ball-only world of the same
  /// field and world options (make_ball_world(world)). When set, the roll continues in it once the
  /// club is clear of the ball ("hand-off", see full_system_putt); nullptr: the arm is simulated
  /// to the end.
  const sim::World* ball_world = nullptr;
  double settle_timeout = 6.0;  ///< [s] to reach the rest pose
  double hit_timeout = 3.0;     ///< [s] from the hit request to contact
  double max_duration = 30.0;   ///< [s] ball roll after the hit
  double launch_delay = 0.02;   ///< [s] after the first contact, when the launch is measured
  /// [s] spacing of the ball trajectory samples in the outcome (from the first contact, time
  /// counted from it; the arm and the ball-only parts alike); 0: no trajectory.
  double record_interval = 0.0;
  sim::OutcomeRules rules{};

  // --- The experiment's ball placement. Zero noise: the run is unchanged, bit for bit.
  /// Std of the ball's placement error around the tee, per horizontal axis. [m]
  double placement_noise = 0.0;
  /// Seed of the putt's randomness (mg::Rng): the placement draws derive_seed(seed, 0); a torque
  /// noise built for the putt draws derive_seed(seed, 1) (PlantWrappers).
  std::uint64_t seed = 0;

  /// Not owned. What the module perceives instead of the simulator's truth (cameras that render
  /// the simulation: vision/camera_perception.hpp); the plant's vision (PlantEffects::perception)
  /// and the stance apply on top. nullptr: the truth.
  perception::PerceptionSource* perception_source = nullptr;

  // --- Where the arm stands (a mobile base beside the ball; robot/wam_model.hpp). The identity:
  // the fixed arm beside the tee. Otherwise the ball starts at the stance's position and the
  // world must have the arm mounted there (make_world_with_arm(field, mount_at(mount, stance))):
  // the module, built for the robot's own frame, perceives ball and hole in it
  // (perception::StancePerception), so its DS, envelope and angles are the same from anywhere.
  robot::Stance stance{};

  /// Throws `InputError` naming the first value out of its documented range (max_duration at
  /// most 600 s, as a ball-only putt).
  void validate() const;
};

/// Angle [rad] (atan2 of the horizontal components) and speed [m/s] of a velocity.
struct AngleSpeed {
  double angle = 0.0;
  double speed = 0.0;
};

struct FullPuttResult {
  bool hit = false;                            ///< the club struck the ball
  std::array<double, 2> ball_start{0.0, 0.0};  ///< [m] where the ball was placed (tee + noise)
  bool hit_refused = false;                    ///< the module refused the request (envelope, NaN)
  sim::PuttOutcome
      outcome;  ///< the ball's outcome; duration [s] and steps count from first contact
  /// Club face velocity just before first contact (speed: 3-D norm) and the ball's velocity
  /// launch_delay after contact (horizontal); angles in the stance's frame (the robot's: the
  /// world's for the identity stance).
  AngleSpeed club;
  AngleSpeed launch;
  /// The ball's whole state when `launch` was measured (world frame; time: the world's clock).
  sim::BallState launch_state;
  CoreTiming timing;
  double max_torque_ratio = 0.0;            ///< max |tau_j| / limit_j of the applied torques
  double max_raw_torque_ratio = 0.0;        ///< the same before the clamp
  double max_velocity_ratio = 0.0;          ///< max |qd_j| / limit_j measured
  double max_command_velocity_ratio = 0.0;  ///< max |qd_des_j| / limit_j commanded by the module
  double min_position_margin = 0.0;         ///< [rad] min distance of a joint to its range ends
  double rest_time = 0.0;  ///< [s] simulated time to reach the rest pose (kAtRestPose: the settle)
  double hit_time = 0.0;   ///< [s] from the hit request to contact
  bool faulted = false;    ///< a fault was observed during the run
  /// Separate club-ball contacts over the run (1: the ball was touched once, as it should be).
  int club_ball_touches = 0;
  bool touching_ball = false;  ///< (bookkeeping of the count: in contact at the last step)
  /// The roll was finished in options.ball_world from handoff_time on. The arm is not simulated
  /// after the hand-off (it brakes or idles away from the ball): the limits above, the touches,
  /// `faulted` and `timing` cover the simulated part only.
  bool handed_off = false;
  double handoff_time = 0.0;  ///< [s] after the first contact (0 without a hand-off)
  /// Ball-only rolls abandoned because the ball came back near where the club was; the arm was
  /// then simulated on from that hand-off, exactly as without one (at most 3).
  int handoff_fallbacks = 0;
  long arm_steps = 0;  ///< physics steps simulated with the arm (rest, hit and roll until hand-off)
  /// Cross-check of the module's hit detection (from measurements: the club's FK path, the
  /// perceived ball) against the simulator's contact: [s] the time of the state in which the
  /// module saw the hit minus the end of the physics step whose contact list first held the
  /// club-ball contact. NaN if either never happened.
  double hit_detection_lag = std::numeric_limits<double>::quiet_NaN();
};

/// Caller-owned scratch of full_system_putt, one per thread (not itself thread-safe): the ball
/// world's mjData, the settled balls of kKinematicApproach / kAtRestPose, and an approach cache
/// for kApproach with an ideal arm and perception (PlantEffects; the 4 latest states at the hit
/// request, keyed by world, module model (address and what of it the approach reads), angle, ball
/// start, hole and settle_timeout; a hit restores the state and skips the simulated approach). It
/// holds memory and caches only, never state that changes a result: a putt gives the same bits with
/// a fresh scratch, a used one, or none (nullptr: made locally, no approach cache). With an
/// approach from the cache, FullPuttResult::timing covers only the core updates run in the call. A
/// scratch must not outlive the module models it was used with.
class PuttScratch {
 public:
  PuttScratch();
  ~PuttScratch();
  PuttScratch(const PuttScratch&) = delete;
  PuttScratch& operator=(const PuttScratch&) = delete;

  struct Impl;  ///< (full_system.cpp)
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// The module's IK fixed point [rad] (7) for the rest pose of `angle` [rad]: where its Rest motion
/// converges (velocity IK iterated from the default posture until it stands still).
robot::Vector7 rest_joint_positions(const ModuleModel& model, double angle);

/// Resets `d`, sets the hole, brings the arm to the rest pose for `angle` (options.rest_start),
/// hits at `speed` and simulates until the ball's outcome is decided, with the true world's
/// `effects` (wrappers bound here, each putt afresh; none: the simulation as it is). Deterministic:
/// the same inputs (options included) give the same bits, on any thread, with any `scratch`.
///
/// Hand-off (options.ball_world set): once the launch is measured, the module is braking or idle
/// (it never hits again in a putt), the club does not touch the ball and the ball's centre is
/// farther from the club head's than R + 5 cm, R = the club's remaining reach (braking:
/// |v_brake0| brake_time + brake_lift_height, a bound on the rest of the ramp; idle: 0) + 5 cm
/// (tracking, drift) + the head's bounding radius + the ball's radius, the ball's state goes to
/// options.ball_world and the roll ends there; the arm is no longer simulated (nor its torque
/// noise: PlantEffects::arm). Should the ball come back within R of where the club head was, the
/// ball-only roll is dropped and the arm simulated on from the hand-off, exactly as without one
/// (handoff_fallbacks; tried again past that time, once the ball is clear, up to 3 times).
/// On return `d` holds the arm as at the hand-off and the ball as at the end.
///
/// `scratch`: per-thread memory (see PuttScratch); nullptr: made locally. Throws InputError for a
/// bad hole or a ball world that does not match `world`; a refused request is reported in the
/// result.
FullPuttResult full_system_putt(const sim::World& world, const ModuleModel& model, mjData* d,
                                std::array<double, 2> hole, double angle, double speed,
                                const FullPuttOptions& options = {}, PuttScratch* scratch = nullptr,
                                const PlantEffects& effects = {});

}  // namespace mg::control
