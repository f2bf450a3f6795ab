// Real-time mode: three threads paced at 500 Hz by the wall clock. Run serially (ctest
// RUN_SERIAL) so the timing is this program's, not the other tests'.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>

#include "system/session.hpp"

namespace mg::system {
using namespace mg::control;
namespace {

TEST(Realtime, HoldsFiveHundredHertzOnTheWallClock) {
  std::ostringstream out;
  SessionOptions options;
  options.realtime = true;
  Session session(ModuleConfig{}, options, out);
  session.execute("speed 1.0");
  session.execute("hit");
  session.execute("wait 3");
  const std::uint64_t ticks = session.core_ticks();
  const std::uint64_t misses = session.deadline_misses();
  // 3 s of wall clock at 500 Hz (the session started a little earlier).
  EXPECT_GE(ticks, 1470u) << out.str();
  EXPECT_LE(ticks, 1600u) << out.str();
  // A loop that cannot keep up misses nearly every tick. The 1 % target is measured by
  // bench/control/realtime_report: this virtual machine's host alone gave 0-23 misses in 1500.
  EXPECT_LT(static_cast<double>(misses), 0.1 * static_cast<double>(ticks)) << out.str();
  const CoreTiming t = session.timing();
  EXPECT_LT(t.core_update_p99_us, 2000.0);
  session.execute("status");
  const std::string text = out.str();
  EXPECT_NE(text.find("Hitting -> Braking: the ball was hit"), std::string::npos) << text;
  EXPECT_NE(text.find("Braking -> Idle"), std::string::npos) << text;
  std::printf(
      "realtime: %llu ticks, %llu deadline misses, core update p99 %.0f us, max %.0f us; %s\n",
      static_cast<unsigned long long>(ticks), static_cast<unsigned long long>(misses),
      t.core_update_p99_us, t.core_update_max_us, session.scheduling().c_str());
}

TEST(Realtime, NormalModeEndToEndOverLoopback) {
  ModuleConfig config;
  config.mode = ModuleMode::kNormal;
  config.vision_port = 0;
  SessionOptions options;
  options.realtime = true;
  options.vision_sim = true;
  std::ostringstream out;
  Session session(config, options, out);
  session.execute("speed 1.0");
  session.execute("hit");
  session.execute("wait 3.5");
  session.execute("status");
  const std::string text = out.str();
  EXPECT_NE(text.find("Rest -> Hitting"), std::string::npos) << text;
  EXPECT_NE(text.find("Hitting -> Braking: the ball was hit"), std::string::npos) << text;
  EXPECT_GT(session.vision_counters().accepted, 100u) << text;
  EXPECT_EQ(session.vision_counters().rejected(), 0u) << text;
}

/// On the core thread after every step: counts them (an observer must not allocate or lock).
class StepCounter final : public SessionObserver {
 public:
  void after_step(const SessionView& v) override {
    steps.fetch_add(1, std::memory_order_relaxed);
    if (v.module.state == ModuleState::kHitting) hitting.store(true, std::memory_order_relaxed);
  }
  std::atomic<long> steps{0};
  std::atomic<bool> hitting{false};
};

// The console's flood (1,000 commands a second, recordings written meanwhile) and a viewer
// inspecting at 60 Hz share nothing with the core thread but lock-free channels: the core keeps
// its ticks, every channel is exercised (run under ThreadSanitizer by scripts/sanitize.sh tsan).
TEST(Realtime, AConsoleFloodAndAViewerLeaveTheCoreOnTime) {
  std::ostringstream out;
  StepCounter counter;
  SessionOptions options;
  options.realtime = true;
  options.observer = &counter;
  Session session(ModuleConfig{}, options, out);
  const auto file = std::filesystem::temp_directory_path() /
                    ("mg_realtime_flood_" + std::to_string(::getpid()) + ".csv");
  std::atomic<bool> done{false};
  std::atomic<long> views{0};
  std::thread viewer([&] {
    while (!done.load()) {
      session.inspect([&](const SessionView& v) {
        if (v.d->time >= 0.0 && v.world.model() != nullptr) views.fetch_add(1);
      });
      std::this_thread::sleep_for(std::chrono::milliseconds(16));
    }
  });
  const char* cycle[] = {"status", "angle 0.1", "speed 1.2", "rest", "angle 0.05", "speed 1.0"};
  const auto start = std::chrono::steady_clock::now();
  auto next = start;
  for (int k = 0; k < 2000; ++k) {
    std::string line = cycle[k % 6];
    if (k % 1000 == 0) line = "hit";
    if (k == 100) line = "record on " + file.string();
    if (k == 1900) line = "record off";
    session.execute(line);
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
  }
  session.execute("status");
  done = true;
  viewer.join();
  const std::uint64_t ticks = session.core_ticks(), misses = session.deadline_misses();
  EXPECT_GE(ticks, 900u) << out.str();
  EXPECT_LT(static_cast<double>(misses), 0.1 * static_cast<double>(ticks)) << out.str();
  EXPECT_GE(counter.steps.load(), static_cast<long>(2 * ticks) - 4);
  EXPECT_TRUE(counter.hitting.load()) << out.str();
  EXPECT_GT(views.load(), 20);
  const std::string text = out.str();
  EXPECT_NE(text.find("recording written: "), std::string::npos) << text;
  EXPECT_NE(text.find("speed 1.2000 m/s"), std::string::npos) << text;
  std::filesystem::remove(file);
  std::printf("realtime flood: %llu ticks, %llu deadline misses, %ld views\n",
              static_cast<unsigned long long>(ticks), static_cast<unsigned long long>(misses),
              views.load());
}

}  // namespace
}  // namespace mg::system
