#pragma once
/// The core side of a console session (system/session.hpp): everything the core thread owns, the
/// core loop (sim_backend/core_loop.hpp) with the session's hooks, and the lock-free channels
/// between it and the rest of the session (ros2_control's real-time buffers):
///
///   user thread  --commands (SPSC queue)-->  core  --events, replies (SPSC queue)-->  printer
///                                            core  --record samples (SPSC ring)----> recorder
///                                            core  --snapshot (triple buffer)------> readers
///   I/O thread   --perception (triple buffer)--> core            (real-time normal mode)
///
/// In real-time mode `apply` and `tick` run on the core thread only; in lockstep mode on the
/// thread that runs the session. Both are real-time safe: no allocation, no I/O, no lock, no
/// throw (an observer's exception becomes a fault of the module: the arm brakes).
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "control/module_config.hpp"
#include "control/recorder.hpp"
#include "core/spsc_queue.hpp"
#include "core/triple_buffer.hpp"
#include "perception/perception.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"
#include "sim_backend/core_loop.hpp"
#include "system/session.hpp"

namespace mg::system {

/// A user request for the core, applied between two ticks. Plain data (the queue copies it).
struct CoreCommand {
  enum class Kind {
    kIdle,
    kRest,
    kHit,
    kAngle,
    kSpeed,
    kAngleSpeed,
    kHole,
    kReset,
    kLoad,
    kRecord
  };
  Kind kind = Kind::kIdle;
  double a = 0.0, b = 0.0;  ///< angle [rad] and speed [m/s], or the hole's x, y [m]
  bool on = false;          ///< kRecord
  const control::ModuleModel* model = nullptr;   ///< kLoad (owned by the session)
  control::ModuleData* data = nullptr;           ///< kLoad (owned by the session)
  const sim::OutcomeTracker* tracker = nullptr;  ///< kHole: prepared for the new hole
  std::uint64_t seq = 0;
};

/// The core's answer to a command (formatted by the printer).
enum class Reply {
  kNone,
  kFaultCleared,        ///< `idle` at standstill acknowledged a fault (a = 1: overrun, b = 1: hook)
  kHitRefusedEnvelope,  ///< a, b: the angle and speed
  kHitAlreadyRunning,
  kGoingToRestFirst,
  kAngle,       ///< a: the angle
  kSpeed,       ///< a: the speed
  kAngleSpeed,  ///< (auto) a, b
  kHole,        ///< a, b: the hole
  kResetRefusedHitting,
  kReset,  ///< a, b: the tee
  kLoadRefusedNotIdle,
  kLoaded,
  kRecordOn,
  kRecordOff,
};

/// What the core tells the printer, in the order it happened.
struct Event {
  enum class Kind { kTransition, kRefused, kOutcome, kNote, kReply, kHookFault } kind = Kind::kNote;
  double t = 0.0;  ///< [s] simulated time
  control::ModuleState from = control::ModuleState::kIdle;
  control::ModuleState to = control::ModuleState::kIdle;
  control::Reason reason = control::Reason::kNoChange;
  sim::PuttEnd end = sim::PuttEnd::kTimeOut;
  bool sunk = false;
  double x = 0.0, y = 0.0, distance = 0.0, duration = 0.0;
  const char* note = "";  ///< kNote: static text
  Reply reply = Reply::kNone;
  double a = 0.0, b = 0.0;       ///< kReply
  std::array<char, 160> what{};  ///< kHookFault: the exception's message
};

/// The session's state as the core last published it (after every tick and applied command).
struct Snapshot {
  double time = 0.0;  ///< [s] simulated
  std::uint64_t ticks = 0;
  ModuleStatus module;
  const control::ModuleModel* model = nullptr;
  double angle = 0.0, speed = 0.0;
  bool hit_armed = false, ball_rolling = false, recording = false;
  std::array<double, 3> ball{};  ///< [m] the simulated ball (truth)
  std::array<double, 3> hole{};  ///< [m] the hole, on the surface
  perception::Perceived seen;    ///< the module's latest perception
  bool fresh = false;            ///< perception_fresh
  std::optional<sim::PuttOutcome> last_outcome;
  /// The pose for a viewer: d->qpos, mocap_pos, mocap_quat, userdata (sized once).
  std::vector<double> qpos, mocap_pos, mocap_quat, userdata;
};

/// Perception handed from a non-real-time thread to the core: the source's answer at `stamp`
/// [s]; the core ages it to its own time.
struct StampedPerception {
  perception::Perceived seen;
  double stamp = 0.0;
};

/// The robot update's perception in real-time normal mode: what the I/O thread last put in
/// `buffer` (it polls the vision feed), aged to the core's clock. The core is the buffer's only
/// reader. Real-time safe.
class BufferedPerception final : public perception::Perception {
 public:
  explicit BufferedPerception(TripleBuffer<StampedPerception>& buffer) : buffer_(&buffer) {}
  perception::Perceived perceive(double now) noexcept override;

 private:
  TripleBuffer<StampedPerception>* buffer_;
};

class SessionCore final : private control::CoreHooks {
 public:
  /// The arm at its default rest posture in Idle, the ball on the tee. `perception`: the robot
  /// update's source (nullptr: the simulator's truth; not owned). `tracker`: prepared for the
  /// current hole (owned by the caller, outlives the core). `observer`: not owned, may be null.
  SessionCore(const sim::World& world, const control::ModuleModel& model, bool realtime,
              SessionObserver* observer, const sim::OutcomeTracker* tracker);
  SessionCore(const SessionCore&) = delete;
  SessionCore& operator=(const SessionCore&) = delete;

  void set_perception(perception::Perception* perception) { loop_.set_perception(perception); }

  /// Applies one command and queues its reply. Real-time safe.
  void apply(const CoreCommand& command) noexcept;
  /// Applies the queued commands. Real-time safe.
  void apply_queued() noexcept;
  /// One core tick, then the fault report and the snapshot. Real-time safe.
  void tick() noexcept;
  /// Publishes the snapshot. Real-time safe.
  void publish() noexcept;
  /// A deadline-overrun streak (the real-time scheduler): the module faults. Real-time safe.
  void overrun_streak() noexcept;

  /// The live state (the core's thread, or lockstep under the session's lock).
  SessionView view() const;
  const mjData* data() const { return d_.get(); }
  const control::CoreLoop& loop() const { return loop_; }

  SpscQueue<CoreCommand, 256> commands;  ///< user -> core
  SpscQueue<Event, 512> events;          ///< core -> printer
  std::atomic<std::uint64_t> events_lost{0};
  /// core -> recorder: 10 s of robot updates between drains.
  SpscQueue<control::RecordSample, 1024> samples;
  std::atomic<std::uint64_t> samples_lost{0};
  TripleBuffer<Snapshot> snapshot;
  std::atomic<std::uint64_t> applied{0};  ///< seq of the last applied command
  /// I/O thread -> core: the vision feed's latest answer (real-time normal mode).
  TripleBuffer<StampedPerception> vision;

 private:
  void after_robot_update(const control::MeasuredState& measured,
                          control::ModuleData& data) override;
  void after_tick(const control::ModuleCommand& command, control::ModuleState before) override;
  void after_step(long step) override;
  void push(const Event& e) noexcept;
  void reply(Reply r, double a = 0.0, double b = 0.0) noexcept;
  ModuleStatus status() const noexcept;

  const sim::World& world_;
  sim::DataPtr d_;
  control::CoreLoop loop_;
  perception::SimulatorPerception truth_;
  SessionObserver* observer_;
  const sim::OutcomeTracker* tracker_proto_;
  std::optional<sim::OutcomeTracker> tracker_;  ///< the ball after a hit, until decided
  double hit_time_ = 0.0;                       ///< [s] simulated time of that hit
  std::optional<sim::PuttOutcome> last_outcome_;
  double angle_ = 0.0;  ///< [rad] the console's current hitting angle
  double speed_ = 1.0;  ///< [m/s] the console's current club speed
  bool hit_when_at_rest_ = false;
  bool recording_ = false;
  std::uint64_t faults_reported_ = 0;
};

template <class Read>
auto Session::read_snapshot(Read&& read) const {
  std::lock_guard lock(snapshot_mutex_);
  return read(core_->snapshot.read());
}

}  // namespace mg::system
