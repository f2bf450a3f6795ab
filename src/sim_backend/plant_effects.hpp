#pragma once
/// The true world's effects on a full-system putt (sim_backend/full_system.hpp), as wrappers of
/// what the harness simulates, in the style of ros2_control's wrapped hardware and sensor
/// interfaces: the plant's arm around the simulated arm (torque noise), the hit request the arm
/// reaches (club speed scale), the plant's vision around the perception (latency, offset:
/// perception/perception.hpp) and what happens to the ball once the club has left it (launch
/// bias). The caller of a putt builds them (system::arm_putt from the plant, a study, a test) and
/// hands them to the harness in a `PlantEffects`; FullPuttOptions keeps the harness's settings.
///
/// The harness binds each wrapper to what it simulates once per putt (`wrap`), which also starts
/// it afresh: a wrapper may be reused, putt after putt, with the bits of a new one. Wrappers hold
/// state while a putt runs: one set per thread. An ideal (identity) wrapper is left out of the
/// putt: it gives the bits of none.
#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "control/arm_interface.hpp"
#include "control/minigolf_module.hpp"
#include "core/rng.hpp"
#include "perception/perception.hpp"
#include "sim/world.hpp"
#include "sim_backend/mujoco_arm.hpp"

namespace mg::control {

/// An arm backend around the simulated arm (the putt's MujocoArm): what the plant's arm does to
/// the commands and measurements. Real-time safe.
class SimArmWrapper : public ArmBackend {
 public:
  /// Wraps `arm` (not owned; the putt's core loop's) and starts afresh.
  virtual void wrap(MujocoArm& arm) noexcept = 0;
  /// Commands act on the simulated arm exactly as written: the harness then leaves the wrapper
  /// out, and may take the approach kinematically or from its cache (both assume an arm that
  /// does what the simulation says).
  virtual bool ideal() const noexcept = 0;
};

/// Execution noise (the launch study, thesis 6.1; a plant's `arm.torque_noise`): a Gaussian
/// joint-torque disturbance of std `fraction` x each joint's torque limit, a fresh draw per joint
/// at every write (every core tick), added to d->qfrc_applied at the arm's dofs after the
/// controller's command reached the motors, for as long as the arm is simulated (rest, hit and
/// roll until the hand-off). The module never reads qfrc_applied.
class TorqueNoiseArm final : public SimArmWrapper {
 public:
  /// `arm`: the limits (the module's model of the arm); `seed` of the draws (a full-system putt's
  /// callers pass derive_seed(FullPuttOptions::seed, 1): stream 0 places the ball). Throws
  /// InputError unless 0 <= fraction <= 1.
  TorqueNoiseArm(const robot::ArmModel& arm, double fraction, std::uint64_t seed);
  void wrap(MujocoArm& arm) noexcept override;
  bool ideal() const noexcept override { return !(fraction_ > 0.0); }
  MeasuredState read() noexcept override { return arm_->read(); }
  void write(const ModuleCommand& command) noexcept override;

 private:
  MujocoArm* arm_ = nullptr;
  double fraction_;
  std::uint64_t seed_;
  Rng rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  robot::Vector7 std_ = robot::Vector7::Zero();
  robot::Vector7 last_ = robot::Vector7::Zero();  ///< the draw in qfrc_applied now
};

/// A hit as the harness asks the module for it.
struct HitRequest {
  double angle = 0.0;  ///< [rad] hitting angle
  double speed = 0.0;  ///< [m/s] club speed
};

/// The hit the plant's arm reaches when a caller asks for `asked`: the harness asks the module for
/// what the arm will reach.
class HitRequestWrapper {
 public:
  virtual ~HitRequestWrapper() = default;
  /// `config`: the module's envelope (what it can be asked for).
  virtual HitRequest reach(const HitRequest& asked, const ControllerConfig& config) const = 0;
  /// `reach` returns `asked` unchanged.
  virtual bool ideal() const noexcept = 0;
};

/// A plant's `arm.club_speed_scale`: the arm reaches `scale` x the commanded club speed, clamped to
/// the envelope [speed_min, speed_max]; the angle as asked.
class ClubSpeedScale final : public HitRequestWrapper {
 public:
  /// Throws InputError unless 0.1 <= scale <= 10.
  explicit ClubSpeedScale(double scale);
  HitRequest reach(const HitRequest& asked, const ControllerConfig& config) const override;
  bool ideal() const noexcept override { return scale_ == 1.0; }

 private:
  double scale_;
};

/// What happens to the ball once the club has left it, before it rolls on (in the arm world or,
/// after the hand-off, the ball world).
class LaunchEffect {
 public:
  virtual ~LaunchEffect() = default;
  /// Called once, after the first physics step in which the club no longer touches the ball:
  /// changes the ball's state in `d` of `world`.
  virtual void after_release(const sim::World& world, mjData* d) const noexcept = 0;
  /// `after_release` changes nothing.
  virtual bool ideal() const noexcept = 0;
};

/// A plant's `arm.launch_angle_bias` (a club face or calibration error the robot does not know
/// of): the ball's horizontal velocity, and its orientation with it (so its body-frame spin turns
/// too), turned about the vertical by `angle` [rad].
class LaunchAngleBias final : public LaunchEffect {
 public:
  /// Throws InputError unless |angle| <= 0.5.
  explicit LaunchAngleBias(double angle);
  void after_release(const sim::World& world, mjData* d) const noexcept override;
  bool ideal() const noexcept override { return angle_ == 0.0; }

 private:
  double angle_;
};

/// The true world's effects on one putt, as the harness takes them: wrappers built by the
/// caller (not owned; they must outlive the putt). nullptr / empty: none (the simulation as it
/// is). An ideal wrapper counts as none.
struct PlantEffects {
  SimArmWrapper* arm = nullptr;
  const HitRequestWrapper* hit = nullptr;
  const LaunchEffect* launch = nullptr;
  /// Around what the module perceives (the truth or options.perception_source), innermost first;
  /// the stance's frame (options.stance) applies on top.
  std::vector<perception::PerceptionWrapper*> perception;

  /// The module's commands act on the simulated arm exactly as written.
  bool ideal_arm() const noexcept { return arm == nullptr || arm->ideal(); }
  /// The module perceives what the simulation (or options.perception_source) shows.
  bool ideal_perception() const noexcept;
};

/// A plant's effects as numbers (plant/plant.hpp's arm and vision, an experiment's execution
/// noise, a stroke's vision error). Identity values: no effect, the bits of none.
struct PlantEffectValues {
  /// Std of the joint-torque noise, a fraction of each joint's torque limit (TorqueNoiseArm). [-]
  double torque_noise = 0.0;
  /// The arm reaches this fraction of the commanded club speed (ClubSpeedScale).
  double club_speed_scale = 1.0;
  /// [rad] The ball's launch is turned by this (LaunchAngleBias).
  double launch_angle_bias = 0.0;
  /// [s] The module perceives the ball and hole this old (perception::DelayedPerception).
  double perception_latency = 0.0;
  /// [m] The module perceives the ball moved by this (perception::OffsetPerception).
  std::array<double, 2> perceived_ball_offset{0.0, 0.0};

  /// Throws InputError naming the first value out of range (torque_noise 0..1, club_speed_scale
  /// 0.1..10, launch_angle_bias +-0.5 rad, perception_latency 0..1 s, the offset +-1 m).
  void validate() const;
};

/// The wrappers of a PlantEffectValues, owned: the usual set a caller builds for a putt.
/// Not copyable (the effects point into it).
class PlantWrappers {
 public:
  /// `model`: the module's (the arm's torque limits); `seed`: the putt's (FullPuttOptions::seed;
  /// the torque noise draws stream derive_seed(seed, 1)). Validates; throws InputError.
  PlantWrappers(const ModuleModel& model, const PlantEffectValues& values, std::uint64_t seed);
  PlantWrappers(const PlantWrappers&) = delete;
  PlantWrappers& operator=(const PlantWrappers&) = delete;

  /// For full_system_putt: the late vision first, then its offset.
  PlantEffects effects();

 private:
  TorqueNoiseArm noise_;
  ClubSpeedScale speed_;
  LaunchAngleBias bias_;
  perception::DelayedPerception late_;
  perception::OffsetPerception off_;
};

}  // namespace mg::control
