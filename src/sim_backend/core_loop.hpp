#pragma once
/// The one core loop of the minigolf module in a simulation: every scheduler runs it, the lockstep
/// putt harness (full_system.hpp), the console's lockstep and real-time modes and the viewer
/// (system/session.hpp). ros2_control's read -> update -> write, libfranka's control callback.
///
/// The loop is the simulator's side (it owns the MuJoCo adapter, sim_backend/mujoco_arm.hpp, and
/// drives it or a plant's arm wrapped around it: set_arm); the module it runs knows no simulator.
///
/// One tick (one core period = steps_per_tick physics steps):
///
///   measured = arm.read()                               the backend: joints and clock
///   every robot_update_divider-th tick:
///     robot_update(model, data, perception(t))          perception and the DS (the robot update)
///     hooks.after_robot_update(measured, data)          e.g. the console's recorder, an armed hit
///   command = module_update(model, data, measured)      the controller
///   arm.write(command)
///   hooks.after_tick(command, state before)             e.g. the console's events
///   steps_per_tick times:
///     hooks.before_step(step); physics step; hooks.after_step(step)
///
/// The core update (module_update and the write) is timed into one TimingHistogram.
///
/// Real-time contract: `tick`, `step` and `tick_without_physics` allocate nothing, do no I/O and
/// never throw. A hook that throws is caught: the module latches a fault (`ModuleData::hook_fault`:
/// a moving arm brakes) and `fault()` reports it until `clear_fault`. Deterministic: the wall
/// clock is measured, never fed back.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>

#include "control/minigolf_module.hpp"
#include "sim/world.hpp"
#include "sim_backend/mujoco_arm.hpp"
#include "sim_backend/simulator_perception.hpp"

namespace mg::control {

/// Wall-clock timing of the core updates of a run.
struct CoreTiming {
  double core_update_p99_us = 0.0;  ///< [us] upper edge of the histogram bin of the 99th percentile
  double core_update_max_us = 0.0;  ///< [us]
  double core_update_mean_us = 0.0;  ///< [us]
  int overruns = 0;                  ///< core updates that took longer than the core period
  int ticks = 0;
};

/// Core-update wall times in log-linear bins (0.8 % wide at most, 1 ns below 256 ns), any length,
/// no allocation. One writer (the loop's thread); `summary` may run on any thread meanwhile (the
/// counters are relaxed atomics: a summary taken during a run may miss the latest tick).
class TimingHistogram {
 public:
  static constexpr int kLinear = 256;  ///< [ns] 1 ns bins below this
  static constexpr int kSub = 128;     ///< bins per octave above it
  static constexpr int kOctaves = 20;  ///< up to 2^28 ns (0.27 s); longer goes to the last bin
  static constexpr int kBins = kLinear + kSub * kOctaves;

  /// Adds one duration [ns]; `budget_ns`: longer counts as an overrun. Real-time safe.
  void add(std::int64_t ns, std::int64_t budget_ns) noexcept;
  CoreTiming summary() const noexcept;
  /// Empties it (the writer only, or while no writer runs).
  void clear() noexcept;

  /// [ns] the lower edge of bin `b` and its width.
  static std::int64_t bin_lower(int b) noexcept;
  static std::int64_t bin_width(int b) noexcept;
  static int bin_of(std::int64_t ns) noexcept;

 private:
  std::array<std::atomic<std::uint32_t>, kBins> bins_{};
  std::atomic<std::uint64_t> count_{0};
  std::atomic<std::uint64_t> over_budget_{0};
  std::atomic<std::int64_t> sum_ns_{0};
  std::atomic<std::int64_t> max_ns_{0};
};

/// What a scheduler does around the loop's tick, on the loop's thread. Every default does nothing.
/// In the real-time console the hooks run inside the 2 ms tick: they must not allocate, block or
/// do I/O. An exception is caught by the loop (a fault: the arm brakes), never passed on.
class CoreHooks {
 public:
  virtual ~CoreHooks() = default;
  /// On robot-update ticks, after robot_update and before module_update: `measured` is what this
  /// tick's module_update will see; `data` may take user requests (request_*).
  virtual void after_robot_update(const MeasuredState& measured, ModuleData& data) {
    (void)measured;
    (void)data;
  }
  /// After the command was written; `before`: the module's state before this tick's update.
  virtual void after_tick(const ModuleCommand& command, ModuleState before) {
    (void)command;
    (void)before;
  }
  /// Around each physics step; `step`: the loop's step count before the step.
  virtual void before_step(long step) { (void)step; }
  virtual void after_step(long step) { (void)step; }
};

/// A hook's exception as the loop caught it.
struct CoreFault {
  std::uint64_t count = 0;       ///< exceptions caught since the loop was made
  double time = 0.0;             ///< [s] simulated time of the latest
  std::array<char, 160> what{};  ///< its message, truncated, NUL-terminated
};

struct CoreLoopOptions {
  /// Physics steps in kImpactSubsteps fine steps while the club head is near the ball
  /// (physics_step): the lockstep schedulers. false: the world's plain step (the real-time
  /// console: 8 fine steps near the ball took the 2 ms tick past its deadline).
  bool fine_impact = true;
};

class CoreLoop {
 public:
  /// The module reset to Idle at the arm's state in `d`. `world`, `model` and `d` must outlive
  /// the loop. Perception defaults to the simulator's ground truth.
  CoreLoop(const sim::World& world, const ModuleModel& model, mjData* d,
           CoreLoopOptions options = {});
  /// The same with the world's ids found already (find_sim_ids(world)).
  CoreLoop(const sim::World& world, const SimIds& ids, const ModuleModel& model, mjData* d,
           CoreLoopOptions options = {});
  CoreLoop(const CoreLoop&) = delete;
  CoreLoop& operator=(const CoreLoop&) = delete;

  /// `perception` (not owned; must outlive the loop) for the robot update, its clock the
  /// simulated time; nullptr: the simulator's ground truth.
  void set_perception(perception::Perception* perception);
  /// Not owned; nullptr: none.
  void set_hooks(CoreHooks* hooks) { hooks_ = hooks; }
  /// `arm` (not owned; must outlive the loop's use of it) is read and written in place of the
  /// simulated arm: a plant's arm wrapping simulated_arm() (sim_backend/plant_effects.hpp).
  /// nullptr: the simulated arm.
  void set_arm(ArmBackend* arm) { arm_ = arm != nullptr ? arm : &sim_arm_; }
  /// The simulated arm (MuJoCo's joints and motors in the loop's data).
  MujocoArm& simulated_arm() { return sim_arm_; }

  /// One physics step; first, on a core-tick boundary, the tick's read -> update -> write.
  void step() noexcept;
  /// Steps to the next core-tick boundary (a whole tick when called on one).
  void tick() noexcept;
  /// The rest of the current core period without physics: on a core-tick boundary the tick's
  /// read -> update -> write; then the clock (d->time) and the step count move on to the next
  /// boundary. For a plant the caller moves itself (kinematic approach).
  void tick_without_physics() noexcept;

  /// Continues from a saved module state and step count (the caller restores `d` to match);
  /// clears timing.
  void restore(const ModuleData& data, long steps);
  /// The module `model` with `data` (not owned; both must outlive the loop) from now on (a
  /// `load hitting`). Real-time safe.
  void replace_module(const ModuleModel& model, ModuleData& data) noexcept;

  ModuleData& module() { return *data_; }
  const ModuleData& module() const { return *data_; }
  const ModuleModel& model() const { return *model_; }
  const sim::World& world() const { return *world_; }
  /// The simulator's ids of the arm, club head and ball in the loop's world.
  const SimIds& ids() const { return ids_; }
  mjData* data() const { return d_; }
  long steps() const { return steps_; }
  int steps_per_tick() const { return steps_per_tick_; }
  /// Core ticks run (any thread).
  std::uint64_t ticks() const { return ticks_.load(std::memory_order_relaxed); }
  /// Core-update wall times of the ticks since the last restore (any thread).
  CoreTiming timing() const { return timing_.summary(); }
  /// The latest hook exception; `fault().count` counts them. The loop's thread, or after it.
  const CoreFault& fault() const { return fault_; }

 private:
  void module_tick() noexcept;
  void physics() noexcept;
  void caught(const char* what) noexcept;
  template <class Call>
  void call_hook(Call&& call) noexcept;

  const sim::World* world_;
  const ModuleModel* model_;
  mjData* d_;
  CoreLoopOptions options_;
  SimIds ids_;
  MujocoArm sim_arm_;
  ArmBackend* arm_;
  std::unique_ptr<ModuleData> own_;  ///< the module data the loop was made with
  ModuleData* data_;
  perception::SimulatorPerception truth_;
  perception::Perception* perception_;
  CoreHooks* hooks_ = nullptr;
  int steps_per_tick_ = 2;
  std::int64_t budget_ns_ = 2'000'000;
  long steps_ = 0;
  std::atomic<std::uint64_t> ticks_{0};
  TimingHistogram timing_;
  CoreFault fault_;
};

}  // namespace mg::control
