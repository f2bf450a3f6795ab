#pragma once
/// A running minigolf system behind `minigolf console`: the field's world with the WAM, the
/// module, its perception (simulator truth, or the network vision feed in normal mode), a
/// parameter model for `auto`, a recorder, and one of two schedulers:
///
///   lockstep (default)  one thread; `wait S` runs S simulated seconds as fast as possible.
///                       Deterministic: the same script gives the same bits.
///   realtime            three threads: the core update + physics at 500 Hz paced by the wall
///                       clock (highest priority), the robot update (perception, DS, recorder,
///                       printing) every robot_update_divider-th period, and the user update
///                       (the console, the calling thread). One mutex guards the module and world;
///                       the robot and user updates hold it for microseconds.
///
/// The module functions (control_tick, robot_update, request_*) are the same in both; only the
/// scheduler differs. Commands are answered on the output stream; state changes, refusals and
/// ball outcomes are printed as they happen. Bad input never throws out of `execute`.
#include <array>
#include <atomic>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

#include "control/console_command.hpp"
#include "control/full_system.hpp"
#include "control/minigolf_module.hpp"
#include "control/module_config.hpp"
#include "control/recorder.hpp"
#include "learning/learner.hpp"
#include "perception/perception.hpp"
#include "perception/vision_feed.hpp"
#include "perception/vision_publisher.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"
#include "system/system.hpp"

namespace mg::system {

using control::CoreTiming;
using control::ModuleConfig;
using control::ModuleState;

/// What an observer of a session sees: everything under the session mutex, read only.
struct SessionView {
  const sim::World& world;
  const mjData* d;
  const control::ModuleModel& model;
  const control::ModuleData& module;
  double angle;                          ///< [rad] the console's hitting angle
  double speed;                          ///< [m/s] the console's club speed
  bool hit_armed;                        ///< `hit` waits for the rest pose
  bool ball_rolling;                     ///< hit, outcome not decided yet
  const sim::PuttOutcome* last_outcome;  ///< the latest decided hit (nullptr: none yet)
};

/// Called by the session after every physics step, under the session mutex, on the thread that
/// steps (lockstep: the caller of execute; realtime: the core thread). It must not keep the view
/// past the call and, in realtime mode, must take microseconds (it delays the next tick). What it
/// does cannot change the simulation: it sees const state only.
class SessionObserver {
 public:
  virtual ~SessionObserver() = default;
  virtual void after_step(const SessionView& view) = 0;
};

struct SessionOptions {
  bool realtime = false;  ///< three threads paced by the wall clock; else lockstep
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

/// Core-update wall time over a whole session in 1 us bins (no allocation, any length).
class TimingHistogram {
 public:
  static constexpr int kBins = 4000;  ///< 0..4 ms; longer times go to the last bin
  void add(double us) noexcept;
  CoreTiming summary(double budget_us) const;

 private:
  std::array<std::uint32_t, kBins> bins_{};
  std::uint64_t count_ = 0;
  std::uint64_t over_budget_ = 0;
  double budget_us_seen_ = 0.0;
  double sum_us_ = 0.0;
  double max_us_ = 0.0;
};

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

  // Observers (thread-safe).
  ModuleState state() const;
  double time() const;  ///< [s] simulated time
  CoreTiming timing() const;
  /// Ticks whose work ended after the next tick was due (realtime mode; 0 in lockstep).
  std::uint64_t deadline_misses() const { return deadline_misses_.load(); }
  std::uint64_t core_ticks() const { return core_ticks_.load(); }
  std::uint16_t vision_port() const;
  perception::VisionCounters vision_counters() const;
  std::array<double, 2> ball_position() const;
  std::string scheduling() const;  ///< the scheduler and the thread priorities it got
  /// Calls `visit` with the session's state under the session mutex (any thread; keep it short:
  /// the scheduler waits meanwhile).
  template <class Visit>
  void inspect(Visit&& visit) const {
    std::lock_guard lock(mutex_);
    visit(view_locked());
  }
  /// Makes a running `wait` return at its next tick and `run` stop before its next line (any
  /// thread; for a viewer whose window was closed).
  void interrupt() { interrupted_ = true; }
  bool interrupted() const { return interrupted_.load(); }

 private:
  struct Event;
  void tick_locked(bool lockstep);
  void robot_tick_locked();
  void push_event_locked(const Event& e);
  void print_events();
  void run_for(double seconds);
  void core_loop();
  void robot_loop();
  void stop_threads();
  void finish_recording();  ///< writes an active recording and says so
  void say(std::string_view text);
  void do_command(const control::ConsoleCommand& command);
  void load_params(const std::string& path);
  std::string scheduling_locked() const;
  SessionView view_locked() const;

  ModuleConfig config_;
  SessionOptions options_;
  std::ostream& out_;
  std::unique_ptr<System> system_;  ///< field worlds, arm, hitting model: built once
  const sim::World& world_;
  sim::DataPtr d_;
  std::unique_ptr<control::ModuleModel>
      model_;  ///< a copy of the system's (`load hitting` replaces it)
  std::unique_ptr<control::ModuleData> md_;
  perception::SimulatorPerception truth_;
  std::unique_ptr<perception::VisionFeed> feed_;
  std::unique_ptr<perception::NetworkPerception> network_;
  std::unique_ptr<perception::VisionPublisher> publisher_;
  perception::Perception* perception_ = nullptr;
  std::optional<learning::Model> params_;
  std::string params_path_;
  control::Recorder recorder_;
  double angle_ = 0.0;  ///< [rad] the console's current hitting angle
  double speed_ = 1.0;  ///< [m/s] the console's current club speed
  bool hit_when_at_rest_ = false;
  std::optional<sim::OutcomeTracker> tracker_;    ///< the ball after a hit, until decided
  double hit_time_ = 0.0;                         ///< [s] simulated time of that hit
  std::optional<sim::PuttOutcome> last_outcome_;  ///< the latest decided hit
  int steps_per_tick_ = 2;
  TimingHistogram timing_;

  static constexpr int kEventCapacity = 256;
  std::unique_ptr<Event[]> events_;
  int event_head_ = 0;
  int event_count_ = 0;
  std::uint64_t events_lost_ = 0;

  mutable std::mutex mutex_;  ///< world, module, perception, recorder, events
  std::mutex out_mutex_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> interrupted_{false};
  std::atomic<std::uint64_t> deadline_misses_{0};
  std::atomic<std::uint64_t> core_ticks_{0};
  std::thread core_thread_;
  std::thread robot_thread_;
  std::string core_priority_;   ///< realtime: what the core thread got (guarded by mutex_)
  std::string robot_priority_;  ///< realtime: what the robot thread got (guarded by mutex_)
};

}  // namespace mg::system
