#include "system/session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <istream>
#include <ostream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "system/session_core.hpp"

namespace mg::system {

using namespace mg::control;  // the module's types, used throughout the session

namespace {

using Clock = std::chrono::steady_clock;

/// Lockstep normal mode: the vision simulator publishes the truth, then the feed is polled (one
/// thread, so the datagram just sent may already be there, as before the core loop).
class PublishingPerception final : public perception::Perception {
 public:
  PublishingPerception(perception::VisionPublisher* publisher, perception::Perception& truth,
                       perception::Perception& network)
      : publisher_(publisher), truth_(&truth), network_(&network) {}
  perception::Perceived perceive(double now) noexcept override {
    if (publisher_ != nullptr) {
      const perception::Perceived t = truth_->perceive(now);
      publisher_->update(now, t.ball, t.hole);
    }
    return network_->perceive(now);
  }

 private:
  perception::VisionPublisher* publisher_;
  perception::Perception* truth_;
  perception::Perception* network_;
};

}  // namespace

// ---- construction ----

Session::Session(const ModuleConfig& config, const SessionOptions& options, std::ostream& out)
    : config_(config),
      options_(options),
      out_(out),
      system_(std::make_unique<System>(config, options.plant)),
      world_(system_->arm_world()),
      scratch_(world_.make_data()),
      display_(world_.make_data()) {
  config_ = system_->config();
  models_.push_back(std::make_unique<ModuleModel>(system_->module()));
  model_ = models_.back().get();
  world_.reset(scratch_.get());
  world_.reset(display_.get());
  core_ = std::make_unique<SessionCore>(world_, *model_, options_.realtime, options_.observer,
                                        tracker_for(world_.hole_position(scratch_.get())));

  if (config_.mode == ModuleMode::kNormal) {
    perception::VisionFeedConfig feed_config;
    feed_config.limits = perception::vision_limits_for(world_.field());
    feed_config.max_age = config_.perception_max_age;
    feed_ = std::make_unique<perception::VisionFeed>(
        perception::UdpReceiver(config_.vision_address,
                                static_cast<std::uint16_t>(config_.vision_port)),
        feed_config);
    network_ = std::make_unique<perception::NetworkPerception>(*feed_);
    if (options_.vision_sim) {
      perception::VisionPublisherConfig pc;
      pc.rate = config_.vision_sim_rate;
      pc.noise = config_.vision_sim_noise;
      pc.latency = config_.vision_sim_latency;
      pc.dropout = config_.vision_sim_dropout;
      pc.seed = options_.seed;
      publisher_ = std::make_unique<perception::VisionPublisher>("127.0.0.1", feed_->port(), pc);
    }
    if (options_.realtime) {
      // The I/O thread polls the feed and runs the vision simulator; the core reads its answer.
      buffered_vision_ = std::make_unique<BufferedPerception>(core_->vision);
      core_->set_perception(buffered_vision_.get());
    } else {
      truth_ = std::make_unique<perception::SimulatorPerception>(world_, core_->data());
      lockstep_vision_ =
          std::make_unique<PublishingPerception>(publisher_.get(), *truth_, *network_);
      core_->set_perception(lockstep_vision_.get());
    }
  } else if (options_.vision_sim) {
    throw InputError(
        "console: --vision-sim needs normal mode (--mode normal, or mode: normal in the config)");
  }
  if (!config_.params_model.empty()) load_params(config_.params_model);
  if (!config_.record.empty()) {
    recorder_.start(config_.record);
    CoreCommand c;
    c.kind = CoreCommand::Kind::kRecord;
    c.on = true;
    send(c);
  }

  const auto hole = world_.hole_position(core_->data());
  const auto [angle, speed] = read_snapshot([](const Snapshot& s) {
    return std::pair<double, double>{s.angle, s.speed};
  });
  say(fmt::format(
      "minigolf console: field {}, mode {}, {}, hole ({:.3f}, {:.3f}), angle {:.3f} rad, speed "
      "{:.3f} m/s{}; type help",
      world_.field().name, to_string(config_.mode), options_.realtime ? "realtime" : "lockstep",
      hole[0], hole[1], angle, speed,
      feed_ ? fmt::format(", vision on udp port {}{}", feed_->port(),
                          publisher_ ? " (built-in vision simulator)" : "")
            : ""));
  if (options_.realtime) {
    stop_ = false;
    threads_running_ = true;
    core_thread_ = std::thread([this] { core_thread(); });
    io_thread_ = std::thread([this] { io_thread(); });
  }
}

Session::~Session() { close(); }

bool Session::close() {
  stop_threads();
  finish_recording();
  return recording_error_.empty();
}

const sim::OutcomeTracker* Session::tracker_for(std::array<double, 2> hole) {
  // Any ball state: the core restarts the tracker from the ball's state at the hit.
  const double position[3] = {0.0, 0.0, 1.0}, velocity[3] = {0.0, 0.0, 0.0};
  sim::OutcomeTracker& t =
      trackers_.emplace_back(world_, hole, sim::OutcomeRules{}, 0.0, position, velocity);
  t.prepare();
  return &t;
}

// ---- the channels to the core ----

void Session::send(const CoreCommand& command) {
  CoreCommand c = command;
  c.seq = ++sent_;
  if (!threads_running_.load()) {
    std::lock_guard lock(mutex_);
    core_->apply(c);
    core_->publish();
    core_->applied.store(c.seq, std::memory_order_release);
    return;
  }
  // Full (the core is 256 commands behind): wait for it, it drains every tick.
  while (!core_->commands.push(c)) std::this_thread::sleep_for(std::chrono::microseconds(200));
}

void Session::sync() {
  if (threads_running_.load()) {
    const auto give_up = Clock::now() + std::chrono::seconds(2);
    while (core_->applied.load(std::memory_order_acquire) < sent_ && Clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  drain_samples();
  print_events();
}

void Session::drain_samples() {
  std::lock_guard lock(recorder_mutex_);
  RecordSample s;
  while (core_->samples.pop(s)) recorder_.record(s);  // counted as dropped when inactive or full
  recorder_.count_dropped(core_->samples_lost.exchange(0, std::memory_order_relaxed));
}

// ---- the schedulers ----

void Session::run_for(double seconds) {
  if (threads_running_.load()) {
    // In slices: an interrupt or a termination signal (Ctrl-C) ends the wait.
    const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(seconds));
    while (Clock::now() < until && !interrupted_.load() &&
           termination_signal() == 0)  // the I/O thread prints meanwhile
      std::this_thread::sleep_for(
          std::min<Clock::duration>(until - Clock::now(), std::chrono::milliseconds(20)));
    sync();
    return;
  }
  const long ticks = std::lround(seconds / config_.core_period());
  const auto start = Clock::now();
  const auto period = std::chrono::duration<double>(config_.core_period());
  for (long k = 0;
       k < ticks && !interrupted_.load(std::memory_order_relaxed) && termination_signal() == 0;
       ++k) {
    {
      std::lock_guard lock(mutex_);
      core_->tick();
    }
    drain_samples();
    print_events();
    if (options_.paced)
      std::this_thread::sleep_until(start +
                                    std::chrono::duration_cast<Clock::duration>(period * (k + 1)));
  }
}

void Session::stop_threads() {
  stop_ = true;
  if (core_thread_.joinable()) core_thread_.join();
  if (io_thread_.joinable()) io_thread_.join();
  threads_running_ = false;
  drain_samples();
  print_events();
}

// ---- the user update ----

void Session::run(std::istream& in, bool prompt) {
  std::string line;
  while (!interrupted_.load()) {
    if (const int sig = termination_signal()) {
      // Ctrl-C, kill, a closed terminal: keep the recording (written first: the output may be
      // gone).
      stop_threads();
      finish_recording();
      say(fmt::format("interrupted by {}: quit", sig == SIGINT    ? "SIGINT"
                                                 : sig == SIGTERM ? "SIGTERM"
                                                 : sig == SIGHUP  ? "SIGHUP"
                                                                  : fmt::format("signal {}", sig)));
      return;
    }
    if (prompt) {
      std::lock_guard lock(printer_mutex_);
      out_ << "minigolf> ";
      out_.flush();
    }
    if (!std::getline(in, line)) {
      if (termination_signal() != 0) continue;  // the read was interrupted by the signal
      say("end of input: quit");
      break;
    }
    if (!execute(line)) break;
  }
  stop_threads();
}

bool Session::execute(std::string_view line) {
  if (options_.echo) {
    if (threads_running_.load()) sync();  // the answers so far before the next command
    say(fmt::format("> {}", line));
  }
  const ConsoleParse parsed = parse_console_line(line);
  if (!parsed.ok()) {
    say(fmt::format("error: {}", parsed.error));
    return true;
  }
  if (std::holds_alternative<QuitCmd>(parsed.command)) {
    sync();
    say("bye");
    return false;
  }
  try {
    do_command(parsed.command);
  } catch (const std::exception& e) {
    say(fmt::format("error: {}", e.what()));
  }
  drain_samples();
  print_events();
  return true;
}

void Session::load_params(const std::string& path) {
  learning::Model m = learning::load_model(resolve_data_path(path));
  if (m.num_inputs() != 2)
    throw InputError(fmt::format("load params: '{}': expected 2 inputs (xi_x, xi_y), got {}", path,
                                 m.num_inputs()));
  const auto& outs = m.output_names;
  if (std::find(outs.begin(), outs.end(), "angle") == outs.end())
    throw InputError(fmt::format("load params: '{}': expected an output named 'angle'", path));
  params_ = std::move(m);
  params_path_ = path;
}

// ---- observers ----

ModuleState Session::state() const {
  return read_snapshot([](const Snapshot& s) { return s.module.state; });
}

double Session::time() const {
  return read_snapshot([](const Snapshot& s) { return s.time; });
}

std::array<double, 2> Session::ball_position() const {
  return read_snapshot([](const Snapshot& s) {
    return std::array<double, 2>{s.ball[0], s.ball[1]};
  });
}

CoreTiming Session::timing() const { return core_->loop().timing(); }

std::uint64_t Session::core_ticks() const { return core_->loop().ticks(); }

std::uint16_t Session::vision_port() const { return feed_ ? feed_->port() : 0; }

perception::VisionCounters Session::vision_counters() const {
  if (!feed_) return {};
  // Lockstep polls the feed in the tick (under mutex_), the real-time I/O thread under io_mutex_.
  std::scoped_lock lock(mutex_, io_mutex_);
  return feed_->counters();
}

std::string Session::scheduling() const {
  if (!options_.realtime) return "lockstep (one thread)";
  const auto describe = [](int priority) {
    return priority >= 0 ? fmt::format("SCHED_FIFO {}", priority)
                         : std::string("default (no permission for SCHED_FIFO)");
  };
  return fmt::format("realtime: core thread {}, I/O thread {}, user thread default",
                     describe(core_priority_.load()), describe(io_priority_.load()));
}

void Session::visit_view(void (*visit)(void*, const SessionView&), void* context) const {
  if (!threads_running_.load()) {
    std::lock_guard lock(mutex_);
    visit(context, core_->view());
    return;
  }
  // The core is not stopped for an observer: the view is what it last published.
  std::lock_guard lock(snapshot_mutex_);
  const Snapshot& s = core_->snapshot.read();
  mjData* d = display_.get();
  const mjModel* m = world_.model();
  std::copy_n(s.qpos.begin(), m->nq, d->qpos);
  std::copy_n(s.mocap_pos.begin(), 3 * m->nmocap, d->mocap_pos);
  std::copy_n(s.mocap_quat.begin(), 4 * m->nmocap, d->mocap_quat);
  std::copy_n(s.userdata.begin(), m->nuserdata, d->userdata);
  d->time = s.time;
  visit(context, SessionView{world_, d, *s.model, s.module, s.angle, s.speed, s.hit_armed,
                             s.ball_rolling, s.last_outcome ? &*s.last_outcome : nullptr});
}

}  // namespace mg::system
