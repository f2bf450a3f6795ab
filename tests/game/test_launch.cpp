// The arm's launch as the game measures it: deterministic without a vision error, spread by it,
// and the oracle's launch error (RoundOptions::oracle_error) of the size the arm shows.
#include "game/launch.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "game/round.hpp"

namespace mg::game {
namespace {

TEST(Launch, TheSameRequestSeenExactlyLaunchesTheSame) {
  system::System sys(system::load_config("", "flat"));
  system::SystemData data(sys);
  const LaunchError e = launch_precision(sys, data, {1.2}, 3, 0.0, 1);
  EXPECT_LT(e.angle, 1e-15);  // the mean of equal values, rounded
  EXPECT_LT(e.speed, 1e-15);
  EXPECT_THROW(launch_precision(sys, data, {1.2}, 1, 0.0, 1), InputError);
}

TEST(Launch, TheOraclesErrorIsTheArmsMeasuredPrecision) {
  system::System sys(system::load_config("", "flat"));
  system::SystemData data(sys);
  const RoundOptions defaults;
  const LaunchError e = launch_precision(sys, data, {0.8, 1.5, 2.1}, 8, defaults.vision_noise, 3);
  EXPECT_GT(e.angle, 0.0);
  EXPECT_GT(e.speed, 0.0);
  // Within a factor of 2.5 either way (eight hits a speed: the estimate itself varies).
  EXPECT_LT(e.angle, 2.5 * defaults.oracle_error.angle);
  EXPECT_GT(e.angle, defaults.oracle_error.angle / 2.5);
  EXPECT_LT(e.speed, 2.5 * defaults.oracle_error.speed);
  EXPECT_GT(e.speed, defaults.oracle_error.speed / 2.5);
}

TEST(Launch, TheLaunchIsReadAlongTheSurface) {
  const field::Field f = field::load_field("flat");
  sim::BallState s{};
  s.qpos = {0.1, 0.0, f.height(0.1, 0.0) + f.ball.radius + 0.004, 1, 0, 0, 0};
  s.qvel = {3.0, 4.0, 0.2, 0.0, 0.0, 0.0};
  const ArmLaunch a = arm_launch(f, {0.0, 0.0}, s);
  EXPECT_NEAR(a.speed, 5.0, 1e-12);
  EXPECT_NEAR(a.angle, std::atan2(4.0, 3.0), 1e-12);
  EXPECT_NEAR(a.club.advance, 0.1 * 0.6, 1e-12);
  EXPECT_NEAR(a.club.lift, 0.004, 1e-9);
  EXPECT_NEAR(a.club.vertical_speed, 0.2, 1e-12);
}

}  // namespace
}  // namespace mg::game
