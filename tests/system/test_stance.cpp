// The ball wherever it lies: the mobile base's stance rule and putts from anywhere on the lane.
#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "system/system.hpp"

namespace mg::system {
namespace {

TEST(Stance, TheTeeOfEveryShippedFieldIsTheIdentity) {
  for (const char* name : {"flat", "arctan", "regular-hill", "multiple-hills"}) {
    const System s(load_config("", name));
    EXPECT_TRUE(stance_for(s, s.field().tee, 0.0).identity()) << name;
    EXPECT_FALSE(stance_for(s, {0.5, 0.1}, 0.0).identity()) << name;
  }
}

TEST(Stance, ToLocalUndoesToWorld) {
  robot::Stance st;
  st.position = {1.2, -0.3, 0.04};
  st.yaw = 2.1;
  const std::array<double, 3> p{0.3, -0.7, 0.2};
  const auto back = st.to_local(st.to_world(p));
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(back[i], p[i], 1e-12);
  // +x of the robot's frame points along the yaw.
  const auto ahead = st.to_world({1.0, 0.0, 0.0});
  EXPECT_NEAR(ahead[0] - st.position[0], std::cos(st.yaw), 1e-12);
  EXPECT_NEAR(ahead[1] - st.position[1], std::sin(st.yaw), 1e-12);
}

// The same request hits the same way from anywhere: the launch, in the stance's frame, is the
// tee's, and the ball leaves along aim + angle in the world.
TEST(Stance, AnArmPuttFromAMovedBallLaunchesAsFromTheTeeAlongTheAim) {
  const System s(load_config("", "flat"));
  SystemData d(s);
  const auto at_tee = arm_putt(s, d, s.field().hole.position, 0.03, 0.8);
  ASSERT_FALSE(at_tee.hit_refused);
  for (const double aim : {-0.4, 0.0, 3.0}) {
    control::FullPuttOptions o;
    o.stance = stance_for(s, {1.0, 0.3}, aim);
    const auto r = arm_putt(s, d, s.field().hole.position, 0.03, 0.8, o);
    ASSERT_FALSE(r.hit_refused) << aim;
    EXPECT_NEAR(r.launch.angle, at_tee.launch.angle, 2e-3) << aim;
    EXPECT_NEAR(r.launch.speed, at_tee.launch.speed, 0.01 * at_tee.launch.speed) << aim;
    const double dx = r.outcome.rest_position[0] - 1.0, dy = r.outcome.rest_position[1] - 0.3;
    EXPECT_GT(std::hypot(dx, dy), 0.1) << aim;
    EXPECT_NEAR(std::remainder(std::atan2(dy, dx) - aim - r.launch.angle, 2 * M_PI), 0.0, 0.02)
        << aim;
  }
}

TEST(Stance, ABallOffTheLaneOrInsideAnObstacleIsAnInputError) {
  const System s(load_config("", "flat"));
  SystemData d(s);
  control::FullPuttOptions o;
  o.stance = stance_for(s, {9.0, 0.0}, 0.0);
  EXPECT_THROW(arm_putt(s, d, s.field().hole.position, 0.0, 0.8, o), InputError);
  EXPECT_THROW(ball_putt(s, d, s.field().hole.position, 0.0, 0.8, 0.0, {{0.0, 5.0}}), InputError);
  EXPECT_THROW(check_ball_position(s.field(), {NAN, 0.0}, "ball"), InputError);
  field::Field f = s.field();
  field::Obstacle block;
  block.type = field::ObstacleType::kBlock;
  block.center = {1.0, 0.0};
  block.size = {0.2, 0.2};
  f.obstacles.push_back(block);
  EXPECT_THROW(check_ball_position(f, {1.0, 0.05}, "ball"), InputError);
  EXPECT_NO_THROW(check_ball_position(f, {1.5, 0.0}, "ball"));
}

TEST(Stance, ABallOnlyPuttFromAStartRollsFromThere) {
  const System s(load_config("", "flat"));
  SystemData d(s);
  const auto tee = ball_putt(s, d, s.field().hole.position, 0.0, 1.0);
  const auto moved = ball_putt(s, d, s.field().hole.position, 0.0, 1.0, 0.0, {{0.5, 0.2}});
  EXPECT_NEAR(moved.rest_position[0] - 0.5, tee.rest_position[0], 1e-3);
  EXPECT_NEAR(moved.rest_position[1] - 0.2, tee.rest_position[1], 1e-3);
}

}  // namespace
}  // namespace mg::system
