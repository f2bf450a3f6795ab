// The console session in lockstep mode: scripted sessions, bad commands, the recorder, normal
// mode over loopback UDP (vision simulator, garbage, stale and lost perception), `auto`.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"
#include "perception/udp.hpp"
#include "perception/vision_message.hpp"
#include "sim_backend/full_system.hpp"
#include "system/session.hpp"
#include "system/system.hpp"

namespace mg::system {
using namespace mg::control;
namespace {

std::string run_script(const std::string& script, const ModuleConfig& config = {},
                       SessionOptions options = {}) {
  std::ostringstream out;
  {
    Session session(config, options, out);
    std::istringstream in(script);
    session.run(in, false);
  }
  return out.str();
}

std::vector<std::string> transitions(const std::string& text) {
  std::vector<std::string> t;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.find(" -> ") != std::string::npos) t.push_back(line.substr(line.find(']') + 2));
  return t;
}

std::filesystem::path temp_dir() {
  const auto dir =
      std::filesystem::temp_directory_path() /
      ("mg_session_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
       ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::create_directories(dir);
  return dir;
}

/// Normal mode listening on any free loopback port.
ModuleConfig normal_mode() {
  ModuleConfig config;
  config.mode = ModuleMode::kNormal;
  config.vision_port = 0;
  return config;
}

TEST(Session, ScriptedSessionGoesRestHittingBrakingIdle) {
  const std::string out =
      run_script("rest\nwait 1.5\nangle 0.1\nspeed 1.0\nhit\nwait 3\nstatus\nquit\n");
  const auto t = transitions(out);
  ASSERT_GE(t.size(), 4u) << out;
  EXPECT_EQ(t[0].rfind("Idle -> Rest", 0), 0u) << out;
  EXPECT_EQ(t[1].rfind("Rest -> Hitting", 0), 0u) << out;
  EXPECT_EQ(t[2], "Hitting -> Braking: the ball was hit") << out;
  EXPECT_EQ(t[3], "Braking -> Idle: all joints stationary") << out;
  EXPECT_NE(out.find("going to the rest pose first"), std::string::npos) << out;  // angle changed
  EXPECT_NE(out.find("ball: "), std::string::npos) << out;
  EXPECT_NE(out.find("state Idle"), std::string::npos) << out;
  EXPECT_NE(out.find("bye"), std::string::npos);
}

TEST(Session, BallLeavesAlongTheCommandedAngle) {
  std::ostringstream out;
  Session session(ModuleConfig{}, {}, out);
  for (const char* line : {"angle 0.2", "speed 0.8", "hit", "wait 3"}) session.execute(line);
  const auto ball = session.ball_position();
  EXPECT_GT(std::hypot(ball[0], ball[1]), 0.15) << out.str();
  EXPECT_NEAR(std::atan2(ball[1], ball[0]), 0.2, 0.02) << out.str();
  EXPECT_EQ(session.state(), ModuleState::kIdle);
}

TEST(Session, BadCommandsAreAnsweredAndChangeNothing) {
  std::ostringstream out;
  Session session(ModuleConfig{}, {}, out);
  const std::vector<std::string> bad = {"fly",
                                        "angle",
                                        "angle abc",
                                        "angle nan",
                                        "angle 5",
                                        "speed -1",
                                        "speed 9",
                                        "hole 99 9",
                                        "hole 1",
                                        "load hitting /nonexistent/model.json",
                                        "load params /nonexistent.json",
                                        "load nothing x",
                                        "record on /nonexistent-dir/x.csv",
                                        "record off",
                                        "auto",
                                        "wait -1",
                                        "wait 1e9",
                                        std::string("\x01\x02\xff", 3)};
  for (const auto& line : bad) EXPECT_TRUE(session.execute(line)) << line;
  EXPECT_EQ(session.state(), ModuleState::kIdle);
  EXPECT_EQ(session.time(), 0.0);
  const std::string text = out.str();
  std::size_t answers = 0;
  for (std::size_t p = 0; (p = text.find('\n', p)) != std::string::npos; ++p) ++answers;
  EXPECT_GE(answers, bad.size() + 1) << text;  // the banner plus one answer per line
  EXPECT_NE(text.find("angle refused"), std::string::npos);
  EXPECT_NE(text.find("speed refused"), std::string::npos);
  EXPECT_NE(text.find("auto refused"), std::string::npos);
}

TEST(Session, LockstepRunsAreBitIdentical) {
  const std::string script =
      "angle -0.1\nspeed 0.9\nhit\nwait 2.5\nreset\nhole 1.2 0.3\nwait 0.2\nquit\n";
  auto strip_timing = [](std::string s) {
    std::string kept;
    std::istringstream in(s);
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("core update:", 0) != 0) kept += line + "\n";
    return kept;
  };
  const std::string a = strip_timing(run_script(script));
  const std::string b = strip_timing(run_script(script));
  EXPECT_EQ(a, b);
  EXPECT_NE(a.find("ball back on the tee"), std::string::npos) << a;
}

/// Counts the steps it sees and keeps the latest ball position (for the observer tests).
class CountingObserver final : public SessionObserver {
 public:
  void after_step(const SessionView& v) override {
    ++steps;
    last_time = v.d->time;
    const mjtNum* b = v.d->qpos + v.world.ids().ball_qpos;
    ball = {b[0], b[1]};
    saw_hitting = saw_hitting || v.module.state == ModuleState::kHitting;
  }
  long steps = 0;
  double last_time = 0.0;
  std::array<double, 2> ball{};
  bool saw_hitting = false;
};

TEST(Session, ObserverSeesEveryStepAndPacingKeepsTheBits) {
  const char* lines[] = {"speed 0.9", "hit", "wait 1.2"};
  std::array<double, 2> plain{};
  {
    std::ostringstream out;
    Session session(ModuleConfig{}, {}, out);
    for (const char* l : lines) session.execute(l);
    plain = session.ball_position();
  }
  CountingObserver observer;
  SessionOptions options;
  options.observer = &observer;
  options.paced = true;
  std::ostringstream out;
  Session session(ModuleConfig{}, options, out);
  const auto start = std::chrono::steady_clock::now();
  for (const char* l : lines) session.execute(l);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto ball = session.ball_position();
  EXPECT_EQ(ball[0], plain[0]);  // bit for bit: observing and pacing change nothing
  EXPECT_EQ(ball[1], plain[1]);
  EXPECT_EQ(observer.ball, ball);
  EXPECT_EQ(observer.steps, 1200);  // 1.2 s of 1 ms steps
  EXPECT_DOUBLE_EQ(observer.last_time, session.time());
  EXPECT_TRUE(observer.saw_hitting);
  EXPECT_GE(wall, 1.19);  // paced: `wait 1.2` took the wall clock's 1.2 s
  session.inspect([&](const SessionView& v) {
    EXPECT_EQ(v.d->time, observer.last_time);
    EXPECT_FALSE(v.hit_armed);
  });
}

TEST(Session, InterruptEndsAPacedWaitAtItsNextTick) {
  SessionOptions options;
  options.paced = true;
  std::ostringstream out;
  Session session(ModuleConfig{}, options, out);
  std::thread closer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    session.interrupt();  // as the viewer does when its window is closed
  });
  const auto start = std::chrono::steady_clock::now();
  session.execute("wait 10");
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  closer.join();
  EXPECT_LT(wall, 2.0);
  EXPECT_GT(session.time(), 0.1);
  EXPECT_LT(session.time(), 2.0);
  std::istringstream in("status\n");
  session.run(in, false);  // interrupted: runs no further line
  EXPECT_EQ(out.str().find("state Idle"), std::string::npos) << out.str();
}

TEST(Session, RecorderWritesOneRowPerRobotUpdate) {
  const auto dir = temp_dir();
  const auto file = dir / "rec.csv";
  std::filesystem::remove(file);
  const std::string out =
      run_script("record on " + file.string() + "\nrest\nwait 1\nrecord off\nquit\n");
  ASSERT_TRUE(std::filesystem::exists(file)) << out;
  const CsvTable csv = read_csv(file);
  EXPECT_EQ(csv.header.front(), "t");
  EXPECT_EQ(csv.header.size(), 2u + 21u + 3u + 3u + 3u + 2u + 3u);
  // 1 s at the 100 Hz robot rate.
  EXPECT_NEAR(static_cast<double>(csv.rows.size()), 100.0, 1.0);
  EXPECT_NE(out.find("recording written: 100 rows"), std::string::npos) << out;
}

TEST(Session, NormalModeHitsWithTheBuiltInVisionSimulator) {
  const ModuleConfig config = normal_mode();
  SessionOptions options;
  options.vision_sim = true;
  const std::string out = run_script("speed 1.0\nhit\nwait 3\nstatus\nquit\n", config, options);
  const auto t = transitions(out);
  ASSERT_GE(t.size(), 3u) << out;
  EXPECT_EQ(t[1].rfind("Rest -> Hitting", 0), 0u) << out;
  EXPECT_EQ(t[2], "Hitting -> Braking: the ball was hit") << out;
  EXPECT_NE(out.find("perception: fresh"), std::string::npos) << out;
}

/// A sender on loopback that plays a misbehaving vision system.
struct Sender {
  perception::UdpSender udp;
  std::uint64_t seq = 0;
  explicit Sender(std::uint16_t port) : udp("127.0.0.1", port) {}
  void good(double ball_x = 0.0) {
    perception::VisionMessage m;
    m.seq = ++seq;
    m.stamp = 0.0;
    m.ball = {ball_x, 0.0, 0.02135};
    m.hole = {2.0, 0.0, 0.0};
    udp.send(perception::format_vision_message(m));
  }
  void garbage() {
    udp.send("{\"format\": \"minigolf-vision/1\", \"seq\": ");
    udp.send("not json at all");
    perception::VisionMessage far;
    far.seq = ++seq;
    far.ball = {50.0, 0.0, 0.0};
    udp.send(perception::format_vision_message(far));  // out of range
    udp.send(std::string(2000, 'x'));                  // too long
  }
};

TEST(Session, NormalModeNeverHitsOnStaleOrBadPerception) {
  const ModuleConfig config = normal_mode();
  std::ostringstream out;
  Session session(config, {}, out);
  Sender sender(session.vision_port());

  // Nothing but garbage: the arm goes to rest but never hits.
  session.execute("speed 0.8");
  session.execute("hit");
  for (int i = 0; i < 150; ++i) {
    sender.garbage();
    session.execute("wait 0.01");
  }
  EXPECT_EQ(session.state(), ModuleState::kRest) << out.str();
  EXPECT_NE(out.str().find("hit refused: no fresh perception"), std::string::npos) << out.str();
  const auto k = session.vision_counters();
  EXPECT_EQ(k.accepted, 0u);
  EXPECT_GE(k.malformed, 300u);
  EXPECT_GE(k.out_of_range, 150u);
  EXPECT_GE(k.too_long, 150u);

  // Good messages that stop: stale after perception_max_age; a hit then is refused.
  for (int i = 0; i < 20; ++i) {
    sender.good();
    session.execute("wait 0.01");
  }
  perception::VisionMessage repeat;
  repeat.seq = 1;
  sender.udp.send(perception::format_vision_message(repeat));
  session.execute("wait 0.01");
  EXPECT_EQ(session.vision_counters().reordered, 1u);
  session.execute("wait 0.5");
  session.execute("hit");
  session.execute("wait 0.2");
  EXPECT_EQ(session.state(), ModuleState::kRest) << out.str();

  // A ball that is not at the hitting point: refused too.
  for (int i = 0; i < 20; ++i) {
    sender.good(0.2);
    session.execute("wait 0.01");
  }
  session.execute("hit");
  for (int i = 0; i < 10; ++i) {
    sender.good(0.2);
    session.execute("wait 0.01");
  }
  EXPECT_EQ(session.state(), ModuleState::kRest) << out.str();
  EXPECT_NE(out.str().find("the ball is not at the hitting point"), std::string::npos) << out.str();
}

TEST(Session, LostPerceptionDuringAHitBrakes) {
  const ModuleConfig config = normal_mode();
  std::ostringstream out;
  Session session(config, {}, out);
  Sender sender(session.vision_port());
  session.execute("speed 0.5");  // slow: the hit lasts longer than perception_max_age
  session.execute("rest");
  for (int i = 0; i < 300 && session.state() != ModuleState::kHitting; ++i) {
    sender.good();
    if (i == 150) session.execute("hit");
    session.execute("wait 0.01");
  }
  ASSERT_EQ(session.state(), ModuleState::kHitting) << out.str();
  session.execute("wait 0.3");  // the vision system goes silent
  EXPECT_NE(session.state(), ModuleState::kHitting);
  EXPECT_NE(out.str().find("Hitting -> Braking: fault"), std::string::npos) << out.str();
  const auto ball = session.ball_position();
  EXPECT_LT(std::hypot(ball[0], ball[1]), 0.005) << "the ball was not touched";
}

/// The whole simulation state after one chosen step (ball, arm, every qpos/qvel/ctrl).
class StepCapture final : public SessionObserver {
 public:
  explicit StepCapture(long at) : at_(at) {}
  void after_step(const SessionView& v) override {
    if (++steps_ != at_) return;
    const mjModel* m = v.world.model();
    qpos.assign(v.d->qpos, v.d->qpos + m->nq);
    qvel.assign(v.d->qvel, v.d->qvel + m->nv);
    ctrl.assign(v.d->ctrl, v.d->ctrl + m->nu);
    time = v.d->time;
  }
  std::vector<double> qpos, qvel, ctrl;
  double time = -1.0;

 private:
  long at_;
  long steps_ = 0;
};

// The console and the putt harness run the one core loop. A console script that asks
// for the rest pose and then for the hit at the tick the putt asked for it gives the putt's bits,
// step for step, through contact and the whole roll.
TEST(Session, AConsoleScriptAndAPuttGiveTheSameBits) {
  const System system(ModuleConfig{});
  const sim::World& world = system.arm_world();
  auto d = world.make_data();
  const double angle = 0.05, speed = 1.5;
  // The simulated approach, the arm simulated to the end (no hand-off, no approach cache).
  const control::FullPuttResult putt = control::full_system_putt(
      world, system.module(), d.get(), world.field().hole.position, angle, speed);
  ASSERT_TRUE(putt.hit);
  ASSERT_FALSE(putt.handed_off);

  StepCapture capture(putt.arm_steps);
  SessionOptions options;
  options.observer = &capture;
  std::ostringstream out;
  Session session(ModuleConfig{}, options, out);
  session.execute("angle 0.05");
  session.execute("speed 1.5");
  session.execute("rest");
  session.execute(fmt::format("wait {:.17g}", putt.rest_time));  // to the putt's hit request
  EXPECT_EQ(session.time(), putt.rest_time) << out.str();
  session.execute("hit");
  session.execute(fmt::format("wait {:.17g}", putt.outcome.duration + 1.0));
  ASSERT_EQ(capture.time, d->time) << out.str();
  const mjModel* m = world.model();
  EXPECT_EQ(capture.qpos, std::vector<double>(d->qpos, d->qpos + m->nq));
  EXPECT_EQ(capture.qvel, std::vector<double>(d->qvel, d->qvel + m->nv));
  EXPECT_EQ(capture.ctrl, std::vector<double>(d->ctrl, d->ctrl + m->nu));
  EXPECT_NE(out.str().find(putt.outcome.sunk ? "ball: holed" : "ball: "), std::string::npos)
      << out.str();
}

/// Throws once, during the hit: a buggy observer (a viewer, a test) on the core's thread.
class ThrowingObserver final : public SessionObserver {
 public:
  void after_step(const SessionView& v) override {
    if (v.module.state == ModuleState::kHitting && !thrown) {
      thrown = true;
      throw std::runtime_error("observer bug");
    }
  }
  bool thrown = false;
};

// A hook's exception is a fault of the module: the arm brakes, the session says why and goes on
// (never std::terminate); `idle` at standstill clears it.
TEST(Session, AnObserversExceptionBrakesTheArmAndIsReported) {
  ThrowingObserver observer;
  SessionOptions options;
  options.observer = &observer;
  std::ostringstream out;
  Session session(ModuleConfig{}, options, out);
  for (const char* line : {"speed 1.0", "hit", "wait 3", "status"}) session.execute(line);
  const std::string text = out.str();
  ASSERT_TRUE(observer.thrown) << text;
  EXPECT_NE(text.find("fault: an observer threw (observer bug)"), std::string::npos) << text;
  EXPECT_NE(text.find("Hitting -> Braking: fault"), std::string::npos) << text;
  EXPECT_EQ(text.find("the ball was hit"), std::string::npos) << text;
  EXPECT_EQ(session.state(), ModuleState::kIdle);
  session.execute("hit");  // refused while the fault lasts
  session.execute("wait 0.1");
  EXPECT_EQ(session.state(), ModuleState::kIdle) << out.str();
  session.execute("idle");
  EXPECT_NE(out.str().find("hook fault cleared"), std::string::npos) << out.str();
  session.execute("hit");
  session.execute("wait 3");
  EXPECT_NE(out.str().find("Hitting -> Braking: the ball was hit"), std::string::npos) << out.str();
}

TEST(Session, AutoTakesAngleAndSpeedFromTheParameterModel) {
  const auto dir = temp_dir();
  // A tiny flat-field data set: aim at the hole, speed grows with distance.
  std::string csv = "xi_x,xi_y,angle,speed\n";
  for (int i = 0; i < 12; ++i) {
    const double x = 1.0 + 0.4 * (i / 4), y = -0.3 + 0.2 * (i % 4);
    csv += std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(std::atan2(y, x)) +
           "," + std::to_string(0.5 + 0.4 * std::hypot(x, y)) + "\n";
  }
  std::ofstream(dir / "data.csv") << csv;
  learning::TrainOptions options;
  options.restarts = 2;
  const learning::Model model = learning::train(learning::load_dataset(dir / "data.csv"), options);
  learning::save_model(model, dir / "params.json");

  std::ostringstream out;
  Session session(ModuleConfig{}, {}, out);
  session.execute("hole 1.5 0.2");
  session.execute("wait 0.05");
  session.execute("load params " + (dir / "params.json").string());
  session.execute("auto");
  EXPECT_NE(out.str().find("auto: xi (1.500, 0.200) -> angle 0.13"), std::string::npos)
      << out.str();
}

}  // namespace
}  // namespace mg::system
