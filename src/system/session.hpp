#pragma once
/// A running minigolf system behind `minigolf console` and `minigolf view`: the field's world
/// with the WAM, the module, its perception (simulator truth, or the network vision feed in normal
/// mode), a parameter model for `auto`, a recorder, on the one core loop
/// (sim_backend/core_loop.hpp) under one of two schedulers:
///
///   lockstep (default)  one thread; `wait S` runs S simulated seconds as fast as possible.
///                       Deterministic: the same script gives the same bits, and the same bits
///                       as a putt asked for at the same tick (tests/system/test_session.cpp).
///   realtime            the core thread (SCHED_FIFO 80 when allowed) runs the core loop at
///                       500 Hz on the wall clock: commands, read -> robot update (every 5th
///                       tick) -> module update -> write -> physics. It shares no lock with the
///                       rest: commands reach it through a single-producer single-consumer queue,
///                       its state leaves through a published snapshot, its events and record
///                       samples through lock-free rings (system/session_core.hpp). An I/O thread
///                       (SCHED_FIFO 60) polls the vision feed, runs the vision simulator, drains
///                       the recorder and prints; the user thread (the caller) parses and answers.
///
/// The module functions are the same in both; only the scheduler differs. Commands are answered
/// on the output stream; state changes, refusals and ball outcomes are printed as they happen. In
/// real-time mode the core answers a command at its next tick: the answer is printed by the I/O
/// thread or at the user's next `status`, `wait`, `quit` (with `echo`, before the next command).
/// Bad input never throws out of `execute`.
#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "control/console_command.hpp"
#include "control/minigolf_module.hpp"
#include "control/module_config.hpp"
#include "control/recorder.hpp"
#include "learning/learner.hpp"
#include "perception/perception.hpp"
#include "perception/vision_feed.hpp"
#include "perception/vision_publisher.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"
#include "sim_backend/core_loop.hpp"
#include "system/system.hpp"

namespace mg::system {

using control::CoreTiming;
using control::ModuleConfig;
using control::ModuleState;

/// The module's state as an observer of a session sees it (a copy: what the core published).
struct ModuleStatus {
  ModuleState state = ModuleState::kIdle;
  bool ball_hit = false;  ///< the module saw the ball hit (latched during a hit)
  bool at_rest_pose = false;
  bool fault = false;     ///< an overrun streak or a hook's exception: cleared by `idle`
  std::int64_t tick = 0;  ///< core ticks since the module's reset
};

/// What an observer of a session sees, read only. `d` is the simulation itself (observers, and
/// `inspect` in lockstep mode) or, in real-time mode's `inspect`, a copy of its pose (qpos, mocap,
/// userdata) as the core last published it.
struct SessionView {
  const sim::World& world;
  const mjData* d;
  const control::ModuleModel& model;
  ModuleStatus module;
  double angle;                          ///< [rad] the console's hitting angle
  double speed;                          ///< [m/s] the console's club speed
  bool hit_armed;                        ///< `hit` waits for the rest pose
  bool ball_rolling;                     ///< hit, outcome not decided yet
  const sim::PuttOutcome* last_outcome;  ///< the latest decided hit (nullptr: none yet)
};

/// Called by the session after every physics step, on the thread that steps (lockstep: the caller
/// of execute; realtime: the core thread). It must not keep the view past the call and, in
/// realtime mode, must take microseconds and must not allocate, lock or do I/O (it runs inside
/// the 2 ms tick). What it does cannot change the simulation: it sees const state only. An
/// exception is caught by the core loop: the module faults (a moving arm brakes) and the session
/// prints it.
class SessionObserver {
 public:
  virtual ~SessionObserver() = default;
  virtual void after_step(const SessionView& view) = 0;
};

struct SessionOptions {
  bool realtime = false;  ///< core, I/O and user threads paced by the wall clock; else lockstep
  /// Lockstep only: `wait S` takes S seconds of wall clock (sleeps between ticks, outside the
  /// mutex), for watching; the simulation is the same bits as unpaced.
  bool paced = false;
  SessionObserver* observer = nullptr;  ///< not owned; must outlive the session
  bool vision_sim = false;  ///< normal mode: the built-in vision simulator publishes on loopback
  bool echo = false;        ///< print every command line before its answer (scripts, logs)
  std::uint64_t seed = 1;   ///< vision simulator noise and dropouts
  /// The world as it really is (plant/plant.hpp). The session's world is built from it (grass,
  /// tilt, the arm's friction and club face); the launch, hole and vision parts act in the putt
  /// harness (system::arm_putt) only, not here.
  plant::Plant plant;
};

class SessionCore;  // system/session_core.hpp
struct CoreCommand;

class Session {
 public:
  /// Loads the field, hitting model and (if configured) parameter model, puts the arm at its
  /// default rest posture in Idle, opens the vision feed in normal mode and starts the threads in
  /// realtime mode. Throws InputError/IoError for bad configuration.
  Session(const ModuleConfig& config, const SessionOptions& options, std::ostream& out);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Executes one console line and answers on the output. Returns false after `quit`.
  /// Never throws: bad commands and failed actions are answered.
  bool execute(std::string_view line);
  /// Reads lines until `quit` or the end of input (then quits). `prompt`: print "minigolf> ".
  /// After mg::defer_termination_signals, a SIGINT/SIGTERM/SIGHUP ends a `wait` and the session
  /// as `quit` does, the recording written first.
  void run(std::istream& in, bool prompt);
  /// Stops the threads and writes an active recording, as the destructor does (idempotent).
  /// False if the recording at the end could not be written (the session said why on its
  /// output, and recording_error() says it again): a program ends with an error then, not with
  /// success.
  bool close();
  const std::string& recording_error() const { return recording_error_; }

  // Observers (thread-safe).
  ModuleState state() const;
  double time() const;  ///< [s] simulated time
  CoreTiming timing() const;
  /// Ticks whose work ended after the next tick was due (realtime mode; 0 in lockstep).
  std::uint64_t deadline_misses() const { return deadline_misses_.load(); }
  std::uint64_t core_ticks() const;
  std::uint16_t vision_port() const;
  perception::VisionCounters vision_counters() const;
  std::array<double, 2> ball_position() const;
  std::string scheduling() const;  ///< the scheduler and the thread priorities it got
  /// Calls `visit` with the session's state (any thread). Lockstep: the live state, under the
  /// session's lock (keep it short: the scheduler waits meanwhile). Realtime: the state the core
  /// last published (the core never waits for it).
  template <class Visit>
  void inspect(Visit&& visit) const {
    auto* target = std::addressof(visit);
    visit_view([](void* v, const SessionView& view) { (*static_cast<decltype(target)>(v))(view); },
               const_cast<void*>(static_cast<const void*>(target)));
  }
  /// Makes a running `wait` return at its next tick and `run` stop before its next line (any
  /// thread; for a viewer whose window was closed).
  void interrupt() { interrupted_ = true; }
  bool interrupted() const { return interrupted_.load(); }

 private:
  void visit_view(void (*visit)(void*, const SessionView&), void* context) const;
  bool realtime() const { return options_.realtime; }
  /// The core applies `command` (lockstep: now; realtime: at its next tick, in order).
  void send(const CoreCommand& command);
  /// Realtime: waits until the core has applied every command sent; then prints the events.
  void sync();
  /// Prints the core's events and replies (any non-real-time thread).
  void print_events();
  /// Moves the core's record samples into the recorder (any non-real-time thread).
  void drain_samples();
  void run_for(double seconds);
  void core_thread();
  void io_thread();
  void stop_threads();
  void finish_recording();  ///< writes an active recording and says so (or why not)
  void say(std::string_view text);
  void do_command(const control::ConsoleCommand& command);
  void do_status();
  void do_auto();
  void do_load_hitting(const std::string& path);
  void do_record(const control::RecordCmd& command);
  void load_params(const std::string& path);
  /// A tracker prepared for the ball after a hit into the hole at `hole` (kept for the session).
  const sim::OutcomeTracker* tracker_for(std::array<double, 2> hole);
  /// Calls `read` with the latest snapshot (under snapshot_mutex_).
  template <class Read>
  auto read_snapshot(Read&& read) const;

  ModuleConfig config_;
  SessionOptions options_;
  std::ostream& out_;
  std::unique_ptr<System> system_;  ///< field worlds, arm, hitting model: built once
  const sim::World& world_;
  /// Every module model and data the session made (`load hitting` adds one; kept to the end, so
  /// a snapshot's model stays valid).
  std::vector<std::unique_ptr<control::ModuleModel>> models_;
  std::vector<std::unique_ptr<control::ModuleData>> datas_;
  const control::ModuleModel* model_ = nullptr;  ///< the core's model, as the user side knows it
  std::deque<sim::OutcomeTracker> trackers_;     ///< one per hole the session had
  sim::DataPtr scratch_;  ///< the user side's: checks a hole before the core sets it
  std::unique_ptr<SessionCore> core_;
  std::uint64_t sent_ = 0;  ///< seq of the last command sent

  // Perception and the vision simulator (normal mode).
  std::unique_ptr<perception::VisionFeed> feed_;
  std::unique_ptr<perception::NetworkPerception> network_;
  std::unique_ptr<perception::VisionPublisher> publisher_;
  std::unique_ptr<perception::SimulatorPerception> truth_;   ///< lockstep: the vision simulator's
  std::unique_ptr<perception::Perception> lockstep_vision_;  ///< lockstep: publish, then poll
  std::unique_ptr<perception::Perception> buffered_vision_;  ///< realtime: the I/O thread's answer

  // The user side.
  std::optional<learning::Model> params_;
  std::string params_path_;
  control::Recorder recorder_;   ///< under recorder_mutex_
  std::string recording_error_;  ///< why the recording at the end was not written (user thread)
  std::uint64_t dropped_reported_ = 0;

  mutable std::mutex mutex_;           ///< lockstep: the core side (the caller's ticks, inspect)
  mutable std::mutex snapshot_mutex_;  ///< the snapshot's readers (never the core)
  mutable std::mutex printer_mutex_;   ///< the event ring's consumers and the output
  mutable std::mutex recorder_mutex_;  ///< the recorder and the sample ring's consumers
  mutable std::mutex io_mutex_;        ///< the vision feed (realtime: the I/O thread polls it)
  sim::DataPtr display_;               ///< realtime `inspect`: the published pose
  std::atomic<bool> stop_{false};
  std::atomic<bool> threads_running_{false};
  std::atomic<bool> interrupted_{false};
  std::atomic<std::uint64_t> deadline_misses_{0};
  std::atomic<int> core_priority_{-2};  ///< SCHED_FIFO priority the thread got (-1: none)
  std::atomic<int> io_priority_{-2};
  std::thread core_thread_;
  std::thread io_thread_;
};

}  // namespace mg::system
