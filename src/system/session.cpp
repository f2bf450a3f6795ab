#include "system/session.hpp"

#include <pthread.h>
#include <sched.h>

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
#include "robot/wam_model.hpp"

namespace mg::system {

using namespace mg::control;  // the module's types, used throughout the scheduler

namespace {

using Clock = std::chrono::steady_clock;

std::filesystem::path resolve_path(const std::string& text) { return resolve_data_path(text); }

/// Tries SCHED_FIFO at `priority`; says what the thread got.
std::string set_thread_priority(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0)
    return fmt::format("SCHED_FIFO {}", priority);
  return "default (no permission for SCHED_FIFO)";
}

std::string format_time(double t) { return fmt::format("[{:8.3f} s]", t); }

}  // namespace

struct Session::Event {
  enum class Kind { kTransition, kRefused, kOutcome, kNote } kind = Kind::kNote;
  double t = 0.0;
  ModuleState from = ModuleState::kIdle;
  ModuleState to = ModuleState::kIdle;
  Reason reason = Reason::kNoChange;
  sim::PuttEnd end = sim::PuttEnd::kTimeOut;
  bool sunk = false;
  double x = 0.0, y = 0.0, distance = 0.0, duration = 0.0;
  const char* note = "";
};

// ---- timing ----

void TimingHistogram::add(double us) noexcept {
  const int bin = std::clamp(static_cast<int>(us), 0, kBins - 1);
  ++bins_[static_cast<std::size_t>(bin)];
  ++count_;
  sum_us_ += us;
  max_us_ = std::max(max_us_, us);
}

CoreTiming TimingHistogram::summary(double budget_us) const {
  CoreTiming t;
  t.ticks = static_cast<int>(count_);
  if (count_ == 0) return t;
  const auto target = static_cast<std::uint64_t>(std::ceil(0.99 * static_cast<double>(count_)));
  std::uint64_t seen = 0;
  for (int b = 0; b < kBins; ++b) {
    seen += bins_[static_cast<std::size_t>(b)];
    if (seen >= target) {
      t.core_update_p99_us = b + 1;  // upper edge of the bin
      break;
    }
  }
  for (int b = static_cast<int>(budget_us); b < kBins; ++b)
    t.overruns += static_cast<int>(bins_[static_cast<std::size_t>(b)]);
  t.core_update_max_us = max_us_;
  t.core_update_mean_us = sum_us_ / static_cast<double>(count_);
  return t;
}

// ---- construction ----

Session::Session(const ModuleConfig& config, const SessionOptions& options, std::ostream& out)
    : config_(config),
      options_(options),
      out_(out),
      system_(std::make_unique<System>(config, options.plant)),
      world_(system_->arm_world()),
      d_(world_.make_data()),
      truth_(world_, d_.get()),
      events_(new Event[kEventCapacity]) {
  config_ = system_->config();
  model_ = std::make_unique<ModuleModel>(system_->module());
  md_ = std::make_unique<ModuleData>(*model_);
  world_.reset(d_.get());
  robot::Vector7 rest;
  for (int j = 0; j < 7; ++j) rest[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  robot::set_joint_positions(model_->arm(), d_.get(), rest);
  mj_forward(world_.model(), d_.get());
  module_reset(*model_, *md_, d_.get());
  steps_per_tick_ = std::max(
      1, static_cast<int>(std::lround(config_.core_period() / world_.model()->opt.timestep)));
  speed_ = std::clamp(1.0, config_.speed_min, model_->speed_cap());

  perception_ = &truth_;
  if (config_.mode == ModuleMode::kNormal) {
    perception::VisionFeedConfig feed_config;
    feed_config.limits = perception::vision_limits_for(world_.field());
    feed_config.max_age = config_.perception_max_age;
    feed_ = std::make_unique<perception::VisionFeed>(
        perception::UdpReceiver(config_.vision_address,
                                static_cast<std::uint16_t>(config_.vision_port)),
        feed_config);
    network_ = std::make_unique<perception::NetworkPerception>(*feed_);
    perception_ = network_.get();
    if (options_.vision_sim) {
      perception::VisionPublisherConfig pc;
      pc.rate = config_.vision_sim_rate;
      pc.noise = config_.vision_sim_noise;
      pc.latency = config_.vision_sim_latency;
      pc.dropout = config_.vision_sim_dropout;
      pc.seed = options_.seed;
      publisher_ = std::make_unique<perception::VisionPublisher>("127.0.0.1", feed_->port(), pc);
    }
  } else if (options_.vision_sim) {
    throw InputError(
        "console: --vision-sim needs normal mode (--mode normal, or mode: normal in the config)");
  }
  if (!config_.params_model.empty()) load_params(config_.params_model);
  if (!config_.record.empty()) recorder_.start(config_.record);

  const auto hole = world_.hole_position(d_.get());
  say(fmt::format(
      "minigolf console: field {}, mode {}, {}, hole ({:.3f}, {:.3f}), angle {:.3f} rad, speed "
      "{:.3f} m/s{}; type help",
      world_.field().name, to_string(config_.mode), options_.realtime ? "realtime" : "lockstep",
      hole[0], hole[1], angle_, speed_,
      feed_ ? fmt::format(", vision on udp port {}{}", feed_->port(),
                          publisher_ ? " (built-in vision simulator)" : "")
            : ""));
  if (options_.realtime) {
    stop_ = false;
    core_thread_ = std::thread([this] { core_loop(); });
    robot_thread_ = std::thread([this] { robot_loop(); });
  }
}

Session::~Session() {
  stop_threads();
  finish_recording();
}

void Session::finish_recording() {
  if (!recorder_.active()) return;
  try {
    const std::size_t n = recorder_.stop();
    say(fmt::format("recording written: {} rows to {}", n, recorder_.path().string()));
  } catch (const Error& e) {
    say(fmt::format("error: {}", e.what()));
  }
}

void Session::stop_threads() {
  stop_ = true;
  if (core_thread_.joinable()) core_thread_.join();
  if (robot_thread_.joinable()) robot_thread_.join();
  print_events();
}

// ---- the updates ----

void Session::push_event_locked(const Event& e) {
  if (event_count_ == kEventCapacity) {
    ++events_lost_;
    return;
  }
  events_[static_cast<std::size_t>((event_head_ + event_count_) % kEventCapacity)] = e;
  ++event_count_;
}

void Session::tick_locked(bool lockstep) {
  ModuleData& md = *md_;
  mjData* d = d_.get();
  if (lockstep && md.tick % config_.robot_update_divider == 0) robot_tick_locked();
  const ModuleState before = md.state;
  MujocoArm arm(model_->arm(), d);
  const auto t0 = Clock::now();
  control_tick(*model_, md, arm);
  timing_.add(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  core_ticks_.fetch_add(1, std::memory_order_relaxed);
  const Reason reason = md.last.reason;
  if (md.state != before) {
    Event e;
    e.kind = Event::Kind::kTransition;
    e.t = d->time;
    e.from = before;
    e.to = md.state;
    e.reason = reason;
    push_event_locked(e);
    if (before == ModuleState::kHitting && reason == Reason::kBallHit) {
      tracker_.emplace(world_, d, sim::OutcomeRules{});
      hit_time_ = d->time;
    }
  } else if (reason != Reason::kNoChange && reason != Reason::kFault) {
    Event e;
    e.kind = Event::Kind::kRefused;
    e.t = d->time;
    e.from = e.to = before;
    e.reason = reason;
    push_event_locked(e);
  }
  for (int s = 0; s < steps_per_tick_; ++s) {
    // Lockstep: the fine impact steps, as every full-system putt. Real time: plain 1 ms steps — the
    // simulator stands in for the arm inside the 2 ms tick, and 8 fine steps near the ball took
    // the tick past its deadline (1.5 % misses measured, against < 1 % allowed).
    if (lockstep)
      physics_step(world_, *model_, d);
    else
      world_.step(d);
    if (tracker_ && tracker_->update(d)) {
      const sim::PuttOutcome o = tracker_->outcome();
      const auto hole = world_.hole_position(d);
      Event e;
      e.kind = Event::Kind::kOutcome;
      e.t = d->time;
      e.end = o.end;
      e.sunk = o.sunk;
      e.x = o.rest_position[0];
      e.y = o.rest_position[1];
      e.distance = std::hypot(o.rest_position[0] - hole[0], o.rest_position[1] - hole[1]);
      e.duration = d->time - hit_time_;
      push_event_locked(e);
      last_outcome_ = o;
      tracker_.reset();
    }
    if (options_.observer) options_.observer->after_step(view_locked());
  }
}

SessionView Session::view_locked() const {
  return SessionView{world_,
                     d_.get(),
                     *model_,
                     *md_,
                     angle_,
                     speed_,
                     hit_when_at_rest_,
                     tracker_.has_value(),
                     last_outcome_ ? &*last_outcome_ : nullptr};
}

void Session::robot_tick_locked() {
  ModuleData& md = *md_;
  const mjData* d = d_.get();
  const double now = d->time;
  if (publisher_) {
    const perception::Perceived t = truth_.perceive(now);
    publisher_->update(now, t.ball, t.hole);
  }
  robot_update(*model_, md, perception_->perceive(now));

  if (recorder_.active()) {
    RecordSample s;
    s.t = now;
    s.state = static_cast<int>(md.state);
    const robot::Vector7 q = robot::joint_positions(model_->arm(), d);
    const robot::Vector7 qd = robot::joint_velocities(model_->arm(), d);
    for (int j = 0; j < 7; ++j) {
      const auto i = static_cast<std::size_t>(j);
      s.q[i] = q[j];
      s.qd[i] = qd[j];
      s.tau[i] = md.tau[j];
    }
    const Eigen::Vector3d face = robot::dh_club_pose(model_->arm(), q).translation();
    s.face = {face.x(), face.y(), face.z()};
    const mjtNum* b = d->qpos + world_.ids().ball_qpos;
    s.ball = {b[0], b[1], b[2]};
    s.seen_ball = md.seen.ball;
    s.seen_hole = {md.seen.hole[0], md.seen.hole[1]};
    s.fresh = perception_fresh(*model_, md);
    s.angle = angle_;
    s.speed = speed_;
    recorder_.record(s);
  }

  // `hit` from Idle or on the way to the rest pose: hit once the rest pose is reached.
  if (hit_when_at_rest_) {
    if (md.state != ModuleState::kRest && md.pending != Command::kRest) {
      hit_when_at_rest_ = false;  // idled, braked or faulted on the way
    } else if (md.at_rest_pose && md.pending == Command::kNone) {
      hit_when_at_rest_ = false;
      request_hit(*model_, md, angle_, speed_);
    }
  }
}

void Session::print_events() {
  std::array<Event, 32> batch;
  for (;;) {
    int n = 0;
    std::uint64_t lost = 0;
    {
      std::lock_guard lock(mutex_);
      while (event_count_ > 0 && n < static_cast<int>(batch.size())) {
        batch[static_cast<std::size_t>(n++)] = events_[static_cast<std::size_t>(event_head_)];
        event_head_ = (event_head_ + 1) % kEventCapacity;
        --event_count_;
      }
      lost = events_lost_;
      events_lost_ = 0;
    }
    if (n == 0 && lost == 0) return;
    for (int i = 0; i < n; ++i) {
      const Event& e = batch[static_cast<std::size_t>(i)];
      switch (e.kind) {
        case Event::Kind::kTransition:
          say(fmt::format("{} {} -> {}: {}", format_time(e.t), to_string(e.from), to_string(e.to),
                          to_string(e.reason)));
          break;
        case Event::Kind::kRefused:
          say(fmt::format("{} {}", format_time(e.t), to_string(e.reason)));
          break;
        case Event::Kind::kOutcome:
          say(
              fmt::format("{} ball: {} at ({:.3f}, {:.3f}), {:.3f} m from the hole, {:.2f} s after "
                          "the hit",
                          format_time(e.t), e.sunk ? "holed" : sim::to_string(e.end), e.x, e.y,
                          e.distance, e.duration));
          break;
        case Event::Kind::kNote:
          say(fmt::format("{} {}", format_time(e.t), e.note));
          break;
      }
    }
    if (lost > 0) say(fmt::format("({} events not shown: printing fell behind)", lost));
  }
}

void Session::run_for(double seconds) {
  if (options_.realtime) {
    // In slices: an interrupt or a termination signal (Ctrl-C) ends the wait.
    const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(seconds));
    while (Clock::now() < until && !interrupted_.load() &&
           termination_signal() == 0)  // the robot thread prints meanwhile
      std::this_thread::sleep_for(
          std::min<Clock::duration>(until - Clock::now(), std::chrono::milliseconds(20)));
    print_events();
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
      tick_locked(true);
    }
    print_events();
    if (options_.paced)
      std::this_thread::sleep_until(start +
                                    std::chrono::duration_cast<Clock::duration>(period * (k + 1)));
  }
}

void Session::core_loop() {
  const std::string priority = set_thread_priority(80);
  {
    std::lock_guard lock(mutex_);
    core_priority_ = priority;
  }
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(config_.core_period()));
  auto due = Clock::now();
  int streak = 0;
  while (!stop_.load(std::memory_order_relaxed)) {
    due += period;
    std::this_thread::sleep_until(due);
    {
      std::lock_guard lock(mutex_);
      tick_locked(false);
    }
    const auto done = Clock::now();
    if (done > due + period) {
      deadline_misses_.fetch_add(1, std::memory_order_relaxed);
      if (++streak >= config_.overrun_streak_limit) {
        std::lock_guard lock(mutex_);
        if (!md_->overrun_fault) {
          md_->overrun_fault = true;
          Event e;
          e.t = d_->time;
          e.note = "overrun streak: the core update missed its deadline too often (fault)";
          push_event_locked(e);
        }
      }
      // Behind by more than a period: skip the missed ticks instead of bursting to catch up.
      if (done > due + 2 * period) due = done - period;
    } else {
      streak = 0;
    }
  }
}

void Session::robot_loop() {
  const std::string priority = set_thread_priority(60);
  {
    std::lock_guard lock(mutex_);
    robot_priority_ = priority;
  }
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(config_.core_period() * config_.robot_update_divider));
  auto due = Clock::now();
  while (!stop_.load(std::memory_order_relaxed)) {
    due += period;
    std::this_thread::sleep_until(due);
    {
      std::lock_guard lock(mutex_);
      robot_tick_locked();
    }
    print_events();
    if (Clock::now() > due + period) due = Clock::now();
  }
}

// ---- the user update ----

void Session::say(std::string_view text) {
  std::lock_guard lock(out_mutex_);
  out_ << text << '\n';
  out_.flush();
}

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
      std::lock_guard lock(out_mutex_);
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
  if (options_.echo) say(fmt::format("> {}", line));
  const ConsoleParse parsed = parse_console_line(line);
  if (!parsed.ok()) {
    say(fmt::format("error: {}", parsed.error));
    return true;
  }
  if (std::holds_alternative<QuitCmd>(parsed.command)) {
    say("bye");
    return false;
  }
  try {
    do_command(parsed.command);
  } catch (const std::exception& e) {
    say(fmt::format("error: {}", e.what()));
  }
  print_events();
  return true;
}

void Session::load_params(const std::string& path) {
  learning::Model m = learning::load_model(resolve_path(path));
  if (m.num_inputs() != 2)
    throw InputError(fmt::format("load params: '{}': expected 2 inputs (xi_x, xi_y), got {}", path,
                                 m.num_inputs()));
  const auto& outs = m.output_names;
  if (std::find(outs.begin(), outs.end(), "angle") == outs.end())
    throw InputError(fmt::format("load params: '{}': expected an output named 'angle'", path));
  params_ = std::move(m);
  params_path_ = path;
}

void Session::do_command(const ConsoleCommand& command) {
  const ModuleConfig& c = config_;
  std::visit(
      [&](const auto& cmd) {
        using T = std::decay_t<decltype(cmd)>;
        if constexpr (std::is_same_v<T, EmptyLine> || std::is_same_v<T, QuitCmd>) {
        } else if constexpr (std::is_same_v<T, HelpCmd>) {
          say(console_help());
        } else if constexpr (std::is_same_v<T, IdleCmd>) {
          std::lock_guard lock(mutex_);
          hit_when_at_rest_ = false;
          request_idle(*md_);
          // `idle` at standstill acknowledges an overrun-streak fault.
          if (md_->state == ModuleState::kIdle && md_->overrun_fault) {
            md_->overrun_fault = false;
            say("overrun fault cleared");
          }
        } else if constexpr (std::is_same_v<T, RestCmd>) {
          std::lock_guard lock(mutex_);
          request_rest(*model_, *md_, angle_);
        } else if constexpr (std::is_same_v<T, HitCmd>) {
          std::lock_guard lock(mutex_);
          ModuleData& md = *md_;
          if (md.state == ModuleState::kRest && md.at_rest_pose && md.pending == Command::kNone &&
              md.angle == angle_) {
            if (!request_hit(*model_, md, angle_, speed_))
              say(fmt::format("hit refused: angle {} rad / speed {} m/s outside the safe envelope",
                              angle_, speed_));
          } else if (md.state == ModuleState::kHitting || md.state == ModuleState::kBraking) {
            say("hit refused: a hit is already running");
          } else {
            if (md.state != ModuleState::kRest || md.angle != angle_)
              request_rest(*model_, md, angle_);
            hit_when_at_rest_ = true;
            say("going to the rest pose first; the hit starts when it is reached");
          }
        } else if constexpr (std::is_same_v<T, AngleCmd>) {
          if (cmd.radians < c.angle_min || cmd.radians > c.angle_max) {
            say(fmt::format("angle refused: {} rad is outside the safe envelope [{}, {}]",
                            cmd.radians, c.angle_min, c.angle_max));
            return;
          }
          std::lock_guard lock(mutex_);
          angle_ = cmd.radians;
          say(fmt::format("angle {:.4f} rad", angle_));
          // At (or on the way to) the rest pose: turn to the new hitting direction.
          if (md_->state == ModuleState::kRest) request_rest(*model_, *md_, angle_);
        } else if constexpr (std::is_same_v<T, SpeedCmd>) {
          const double v = cmd.metres_per_second;
          if (v < c.speed_min || v > model_->speed_cap()) {
            say(fmt::format("speed refused: {} m/s is outside the safe envelope [{}, {}]", v,
                            c.speed_min, model_->speed_cap()));
            return;
          }
          std::lock_guard lock(mutex_);
          speed_ = v;
          say(fmt::format("speed {:.4f} m/s", speed_));
        } else if constexpr (std::is_same_v<T, AutoCmd>) {
          if (!params_) {
            say("auto refused: no parameter model loaded (load params FILE)");
            return;
          }
          perception::Perceived seen;
          bool fresh = false;
          {
            std::lock_guard lock(mutex_);
            seen = md_->seen;
            fresh = perception_fresh(*model_, *md_);
          }
          if (!fresh) {
            say("auto refused: no fresh perception of ball and hole");
            return;
          }
          Eigen::MatrixXd xi(1, 2);
          xi << seen.hole[0] - seen.ball[0], seen.hole[1] - seen.ball[1];
          const learning::Predictions p = learning::predict(*params_, xi);
          double angle = angle_, speed = speed_;
          for (int k = 0; k < params_->num_outputs(); ++k) {
            const std::string& name = params_->output_names[static_cast<std::size_t>(k)];
            if (name == "angle") angle = p.mean(0, k);
            if (name == "speed") speed = p.mean(0, k);
          }
          if (!std::isfinite(angle) || !std::isfinite(speed) || angle < c.angle_min ||
              angle > c.angle_max || speed < c.speed_min || speed > model_->speed_cap()) {
            say(
                fmt::format("auto refused: the model predicts angle {} rad, speed {} m/s for xi "
                            "({:.3f}, {:.3f}), outside the safe envelope",
                            angle, speed, xi(0, 0), xi(0, 1)));
            return;
          }
          std::lock_guard lock(mutex_);
          angle_ = angle;
          speed_ = speed;
          say(fmt::format("auto: xi ({:.3f}, {:.3f}) -> angle {:.4f} rad, speed {:.4f} m/s",
                          xi(0, 0), xi(0, 1), angle_, speed_));
          if (md_->state == ModuleState::kRest) request_rest(*model_, *md_, angle_);
        } else if constexpr (std::is_same_v<T, HoleCmd>) {
          field::check_hole_position(world_.field(), {cmd.x, cmd.y});
          std::lock_guard lock(mutex_);
          world_.set_hole(d_.get(), {cmd.x, cmd.y});
          say(fmt::format("hole at ({:.3f}, {:.3f})", cmd.x, cmd.y));
        } else if constexpr (std::is_same_v<T, ResetCmd>) {
          std::lock_guard lock(mutex_);
          if (md_->state == ModuleState::kHitting) {
            say("reset refused: the arm is hitting");
            return;
          }
          const auto& tee = world_.field().tee;
          world_.place_ball(d_.get(), {tee[0], tee[1]});
          tracker_.reset();
          say(fmt::format("ball back on the tee ({:.3f}, {:.3f})", tee[0], tee[1]));
        } else if constexpr (std::is_same_v<T, LoadCmd>) {
          if (cmd.what == LoadCmd::What::kParams) {
            load_params(cmd.path);
            say(fmt::format("parameter model loaded: {} ({}, outputs {})", cmd.path,
                            learning::method_name(params_->method),
                            fmt::join(params_->output_names, ", ")));
            return;
          }
          ds::HittingModel hitting = ds::read_hitting_model(resolve_path(cmd.path));
          auto model =
              std::make_unique<ModuleModel>(make_module_model(world_, std::move(hitting), config_));
          auto data = std::make_unique<ModuleData>(*model);
          std::lock_guard lock(mutex_);
          if (md_->state != ModuleState::kIdle) {
            say("load hitting refused: send idle first (the module must be Idle)");
            return;
          }
          module_reset(*model, *data, d_.get());  // perception stale until the next robot update
          model_.swap(model);
          md_.swap(data);
          say(fmt::format("hitting model loaded: {}", cmd.path));
        } else if constexpr (std::is_same_v<T, RecordCmd>) {
          std::lock_guard lock(mutex_);
          if (cmd.on) {
            recorder_.start(cmd.path);
            say(fmt::format("recording to {}", cmd.path));
          } else if (!recorder_.active()) {
            say("not recording");
          } else {
            const std::size_t dropped = recorder_.dropped();
            const std::size_t n = recorder_.stop();
            say(fmt::format(
                "recording written: {} rows to {}{}", n, recorder_.path().string(),
                dropped ? fmt::format(" ({} rows dropped: buffer full)", dropped) : ""));
          }
        } else if constexpr (std::is_same_v<T, WaitCmd>) {
          run_for(cmd.seconds);
        } else if constexpr (std::is_same_v<T, StatusCmd>) {
          std::string text;
          {
            std::lock_guard lock(mutex_);
            const ModuleData& md = *md_;
            const mjData* d = d_.get();
            const mjtNum* b = d->qpos + world_.ids().ball_qpos;
            const auto hole = world_.hole_position(d);
            const CoreTiming t = timing_.summary(config_.core_period() * 1e6);
            text += fmt::format("time {:.3f} s, state {}, angle {:.4f} rad, speed {:.4f} m/s{}\n",
                                d->time, to_string(md.state), angle_, speed_,
                                hit_when_at_rest_ ? " (hit armed)" : "");
            text += fmt::format("ball ({:.3f}, {:.3f}, {:.3f}), hole ({:.3f}, {:.3f})\n", b[0],
                                b[1], b[2], hole[0], hole[1]);
            text += fmt::format("perception: {}, ball ({:.3f}, {:.3f}), hole ({:.3f}, {:.3f})\n",
                                perception_fresh(*model_, md) ? "fresh" : "STALE", md.seen.ball[0],
                                md.seen.ball[1], md.seen.hole[0], md.seen.hole[1]);
            if (feed_) {
              const auto& k = feed_->counters();
              text += fmt::format(
                  "vision feed: port {}, accepted {}, rejected {} (malformed {}, out of range {}, "
                  "reordered {}, too long {})\n",
                  feed_->port(), k.accepted, k.rejected(), k.malformed, k.out_of_range, k.reordered,
                  k.too_long);
            }
            text += fmt::format("params: {}\n", params_ ? params_path_ : std::string("none"));
            text += fmt::format(
                "recording: {}\n",
                recorder_.active()
                    ? fmt::format("{} ({} rows)", recorder_.path().string(), recorder_.rows())
                    : std::string("off"));
            text += fmt::format(
                "core update: {} ticks, p99 {:.0f} us, max {:.0f} us, over budget {}, deadline "
                "misses {}; scheduling {}",
                t.ticks, t.core_update_p99_us, t.core_update_max_us, t.overruns,
                deadline_misses_.load(), scheduling_locked());
          }
          say(text);
        }
      },
      command);
}

// ---- observers ----

ModuleState Session::state() const {
  std::lock_guard lock(mutex_);
  return md_->state;
}

double Session::time() const {
  std::lock_guard lock(mutex_);
  return d_->time;
}

CoreTiming Session::timing() const {
  std::lock_guard lock(mutex_);
  return timing_.summary(config_.core_period() * 1e6);
}

std::string Session::scheduling_locked() const {
  if (!options_.realtime) return "lockstep (one thread)";
  return fmt::format("realtime: core thread {}, robot thread {}, user thread default",
                     core_priority_, robot_priority_);
}

std::string Session::scheduling() const {
  std::lock_guard lock(mutex_);
  return scheduling_locked();
}

std::uint16_t Session::vision_port() const { return feed_ ? feed_->port() : 0; }

perception::VisionCounters Session::vision_counters() const {
  std::lock_guard lock(mutex_);
  return feed_ ? feed_->counters() : perception::VisionCounters{};
}

std::array<double, 2> Session::ball_position() const {
  std::lock_guard lock(mutex_);
  const mjtNum* b = d_->qpos + world_.ids().ball_qpos;
  return {b[0], b[1]};
}

}  // namespace mg::system
