// The session's user side: console commands checked and turned into core commands, the answers
// and events printed, the recording written. Never on the core thread.
#include <algorithm>
#include <cmath>
#include <ostream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "sim_backend/full_system.hpp"
#include "system/session.hpp"
#include "system/session_core.hpp"

namespace mg::system {

using namespace mg::control;

namespace {

std::string format_time(double t) { return fmt::format("[{:8.3f} s]", t); }

/// The text of a core reply (empty: the user side answered already).
std::string reply_text(const Event& e) {
  switch (e.reply) {
    case Reply::kFaultCleared:
      return e.a != 0.0 && e.b != 0.0 ? "overrun and hook faults cleared"
             : e.a != 0.0             ? "overrun fault cleared"
                                      : "hook fault cleared";
    case Reply::kHitRefusedEnvelope:
      return fmt::format("hit refused: angle {} rad / speed {} m/s outside the safe envelope", e.a,
                         e.b);
    case Reply::kHitAlreadyRunning:
      return "hit refused: a hit is already running";
    case Reply::kGoingToRestFirst:
      return "going to the rest pose first; the hit starts when it is reached";
    case Reply::kAngle:
      return fmt::format("angle {:.4f} rad", e.a);
    case Reply::kSpeed:
      return fmt::format("speed {:.4f} m/s", e.a);
    case Reply::kHole:
      return fmt::format("hole at ({:.3f}, {:.3f})", e.a, e.b);
    case Reply::kResetRefusedHitting:
      return "reset refused: the arm is hitting";
    case Reply::kReset:
      return fmt::format("ball back on the tee ({:.3f}, {:.3f})", e.a, e.b);
    case Reply::kLoadRefusedNotIdle:
      return "load hitting refused: send idle first (the module must be Idle)";
    case Reply::kNone:
    case Reply::kAngleSpeed:
    case Reply::kLoaded:
    case Reply::kRecordOn:
    case Reply::kRecordOff:
      break;
  }
  return {};
}

std::string event_text(const Event& e) {
  switch (e.kind) {
    case Event::Kind::kTransition:
      return fmt::format("{} {} -> {}: {}", format_time(e.t), to_string(e.from), to_string(e.to),
                         to_string(e.reason));
    case Event::Kind::kRefused:
      return fmt::format("{} {}", format_time(e.t), to_string(e.reason));
    case Event::Kind::kOutcome:
      return fmt::format(
          "{} ball: {} at ({:.3f}, {:.3f}), {:.3f} m from the hole, {:.2f} s after the hit",
          format_time(e.t), e.sunk ? "holed" : sim::to_string(e.end), e.x, e.y, e.distance,
          e.duration);
    case Event::Kind::kNote:
      return fmt::format("{} {}", format_time(e.t), e.note);
    case Event::Kind::kHookFault:
      return fmt::format("{} fault: an observer threw ({}); the arm brakes (idle clears it)",
                         format_time(e.t), e.what.data());
    case Event::Kind::kReply:
      return reply_text(e);
  }
  return {};
}

}  // namespace

void Session::say(std::string_view text) {
  std::lock_guard lock(printer_mutex_);
  out_ << text << '\n';
  out_.flush();
}

void Session::print_events() {
  std::lock_guard lock(printer_mutex_);
  Event e;
  while (core_->events.pop(e)) {
    const std::string text = event_text(e);
    if (!text.empty()) out_ << text << '\n';
  }
  if (const auto lost = core_->events_lost.exchange(0, std::memory_order_relaxed))
    out_ << fmt::format("({} events not shown: printing fell behind)\n", lost);
  out_.flush();
}

void Session::finish_recording() {
  {
    std::lock_guard lock(recorder_mutex_);
    if (!recorder_.active()) return;
  }
  CoreCommand off;
  off.kind = CoreCommand::Kind::kRecord;
  off.on = false;
  send(off);
  sync();
  try {
    std::lock_guard lock(recorder_mutex_);
    const std::size_t n = recorder_.stop();
    say(fmt::format("recording written: {} rows to {}", n, recorder_.path().string()));
  } catch (const Error& e) {
    recording_error_ = e.what();
    say(fmt::format("error: {}", e.what()));
  }
}

void Session::do_command(const ConsoleCommand& command) {
  const ModuleConfig& c = config_;
  std::visit(
      [&](const auto& cmd) {
        using T = std::decay_t<decltype(cmd)>;
        CoreCommand core;
        if constexpr (std::is_same_v<T, EmptyLine> || std::is_same_v<T, QuitCmd>) {
        } else if constexpr (std::is_same_v<T, HelpCmd>) {
          say(console_help());
        } else if constexpr (std::is_same_v<T, IdleCmd>) {
          core.kind = CoreCommand::Kind::kIdle;
          send(core);
        } else if constexpr (std::is_same_v<T, RestCmd>) {
          core.kind = CoreCommand::Kind::kRest;
          send(core);
        } else if constexpr (std::is_same_v<T, HitCmd>) {
          core.kind = CoreCommand::Kind::kHit;
          send(core);
        } else if constexpr (std::is_same_v<T, AngleCmd>) {
          if (cmd.radians < c.angle_min || cmd.radians > c.angle_max) {
            say(fmt::format("angle refused: {} rad is outside the safe envelope [{}, {}]",
                            cmd.radians, c.angle_min, c.angle_max));
            return;
          }
          core.kind = CoreCommand::Kind::kAngle;
          core.a = cmd.radians;
          send(core);
        } else if constexpr (std::is_same_v<T, SpeedCmd>) {
          const double v = cmd.metres_per_second;
          if (v < c.speed_min || v > model_->speed_cap()) {
            say(fmt::format("speed refused: {} m/s is outside the safe envelope [{}, {}]", v,
                            c.speed_min, model_->speed_cap()));
            return;
          }
          core.kind = CoreCommand::Kind::kSpeed;
          core.a = v;
          send(core);
        } else if constexpr (std::is_same_v<T, AutoCmd>) {
          do_auto();
        } else if constexpr (std::is_same_v<T, HoleCmd>) {
          // Checked here, on a scratch copy (a bad or too steep hole is an error, as before); the
          // core only places it.
          field::check_hole_position(world_.field(), {cmd.x, cmd.y});
          world_.set_hole(scratch_.get(), {cmd.x, cmd.y});
          core.kind = CoreCommand::Kind::kHole;
          core.a = cmd.x;
          core.b = cmd.y;
          core.tracker = tracker_for({cmd.x, cmd.y});
          send(core);
        } else if constexpr (std::is_same_v<T, ResetCmd>) {
          core.kind = CoreCommand::Kind::kReset;
          send(core);
        } else if constexpr (std::is_same_v<T, LoadCmd>) {
          if (cmd.what == LoadCmd::What::kParams) {
            load_params(cmd.path);
            say(fmt::format("parameter model loaded: {} ({}, outputs {})", cmd.path,
                            learning::method_name(params_->method),
                            fmt::join(params_->output_names, ", ")));
            return;
          }
          do_load_hitting(cmd.path);
        } else if constexpr (std::is_same_v<T, RecordCmd>) {
          do_record(cmd);
        } else if constexpr (std::is_same_v<T, WaitCmd>) {
          run_for(cmd.seconds);
        } else if constexpr (std::is_same_v<T, StatusCmd>) {
          do_status();
        }
      },
      command);
}

void Session::do_auto() {
  const ModuleConfig& c = config_;
  if (!params_) {
    say("auto refused: no parameter model loaded (load params FILE)");
    return;
  }
  sync();
  const auto [seen, fresh] = read_snapshot([](const Snapshot& s) {
    return std::pair<perception::Perceived, bool>{s.seen, s.fresh};
  });
  if (!fresh) {
    say("auto refused: no fresh perception of ball and hole");
    return;
  }
  Eigen::MatrixXd xi(1, 2);
  xi << seen.hole[0] - seen.ball[0], seen.hole[1] - seen.ball[1];
  const learning::Predictions p = learning::predict(*params_, xi);
  double angle = read_snapshot([](const Snapshot& s) { return s.angle; });
  double speed = read_snapshot([](const Snapshot& s) { return s.speed; });
  for (int k = 0; k < params_->num_outputs(); ++k) {
    const std::string& name = params_->output_names[static_cast<std::size_t>(k)];
    if (name == "angle") angle = p.mean(0, k);
    if (name == "speed") speed = p.mean(0, k);
  }
  if (!std::isfinite(angle) || !std::isfinite(speed) || angle < c.angle_min ||
      angle > c.angle_max || speed < c.speed_min || speed > model_->speed_cap()) {
    say(fmt::format(
        "auto refused: the model predicts angle {} rad, speed {} m/s for xi ({:.3f}, {:.3f}), "
        "outside the safe envelope",
        angle, speed, xi(0, 0), xi(0, 1)));
    return;
  }
  CoreCommand core;
  core.kind = CoreCommand::Kind::kAngleSpeed;
  core.a = angle;
  core.b = speed;
  send(core);
  say(fmt::format("auto: xi ({:.3f}, {:.3f}) -> angle {:.4f} rad, speed {:.4f} m/s", xi(0, 0),
                  xi(0, 1), angle, speed));
}

void Session::do_load_hitting(const std::string& path) {
  // Built here (it allocates); the core only switches to it, and only in Idle.
  ds::HittingModel hitting = ds::read_hitting_model(resolve_data_path(path));
  auto model =
      std::make_unique<ModuleModel>(make_module_model(world_, std::move(hitting), config_));
  auto data = std::make_unique<ModuleData>(*model);
  CoreCommand core;
  core.kind = CoreCommand::Kind::kLoad;
  core.model = model.get();
  core.data = data.get();
  send(core);
  sync();  // prints a refusal
  const bool loaded = read_snapshot([&](const Snapshot& s) { return s.model == model.get(); });
  if (!loaded) return;  // the core never used them
  model_ = model.get();
  models_.push_back(std::move(model));
  datas_.push_back(std::move(data));
  say(fmt::format("hitting model loaded: {}", path));
}

void Session::do_record(const RecordCmd& cmd) {
  CoreCommand core;
  core.kind = CoreCommand::Kind::kRecord;
  if (cmd.on) {
    {
      std::lock_guard lock(recorder_mutex_);
      recorder_.start(cmd.path);
    }
    core.on = true;
    send(core);
    say(fmt::format("recording to {}", cmd.path));
    return;
  }
  {
    std::lock_guard lock(recorder_mutex_);
    if (!recorder_.active()) {
      say("not recording");
      return;
    }
  }
  core.on = false;
  send(core);
  sync();  // every sample the core took is in the ring now, and drained
  // Formatted and written here, on the user thread: the core runs on meanwhile.
  std::lock_guard lock(recorder_mutex_);
  const std::size_t dropped = recorder_.dropped();
  const std::size_t n = recorder_.stop();
  say(fmt::format("recording written: {} rows to {}{}", n, recorder_.path().string(),
                  dropped ? fmt::format(" ({} rows dropped: buffer full)", dropped) : ""));
}

void Session::do_status() {
  sync();
  const CoreTiming t = timing();
  std::string text = read_snapshot([&](const Snapshot& s) {
    std::string out;
    out +=
        fmt::format("time {:.3f} s, state {}, angle {:.4f} rad, speed {:.4f} m/s{}\n", s.time,
                    to_string(s.module.state), s.angle, s.speed, s.hit_armed ? " (hit armed)" : "");
    out += fmt::format("ball ({:.3f}, {:.3f}, {:.3f}), hole ({:.3f}, {:.3f})\n", s.ball[0],
                       s.ball[1], s.ball[2], s.hole[0], s.hole[1]);
    out += fmt::format("perception: {}, ball ({:.3f}, {:.3f}), hole ({:.3f}, {:.3f})\n",
                       s.fresh ? "fresh" : "STALE", s.seen.ball[0], s.seen.ball[1], s.seen.hole[0],
                       s.seen.hole[1]);
    return out;
  });
  if (feed_) {
    const perception::VisionCounters k = vision_counters();
    text += fmt::format(
        "vision feed: port {}, accepted {}, rejected {} (malformed {}, out of range {}, "
        "reordered {}, too long {})\n",
        feed_->port(), k.accepted, k.rejected(), k.malformed, k.out_of_range, k.reordered,
        k.too_long);
  }
  text += fmt::format("params: {}\n", params_ ? params_path_ : std::string("none"));
  {
    std::lock_guard lock(recorder_mutex_);
    text += fmt::format("recording: {}\n",
                        recorder_.active() ? fmt::format("{} ({} rows)", recorder_.path().string(),
                                                         recorder_.rows())
                                           : std::string("off"));
  }
  text += fmt::format(
      "core update: {} ticks, p99 {:.0f} us, max {:.0f} us, over budget {}, deadline misses {}; "
      "scheduling {}",
      t.ticks, t.core_update_p99_us, t.core_update_max_us, t.overruns, deadline_misses_.load(),
      scheduling());
  say(text);
}

}  // namespace mg::system
