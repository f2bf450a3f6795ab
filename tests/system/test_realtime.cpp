// Real-time mode: three threads paced at 500 Hz by the wall clock. Run serially (ctest
// RUN_SERIAL) so the timing is this program's, not the other tests'.
#include <gtest/gtest.h>

#include <sstream>

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

}  // namespace
}  // namespace mg::system
