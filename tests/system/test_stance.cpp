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

// The stance rule for hits in world terms: within the fixed arm's reach the base faces +x (the
// thesis's data keep their meaning); beyond it the base turns to the hitting direction.
TEST(HitPose, TheBaseTurnsOnlyForHitsTheFixedArmCannotMake) {
  const System s(load_config("", "flat"));
  const auto& c = s.config();
  const std::array<double, 2> tee = s.field().tee, ball{0.8, 0.2};
  HitPose p = hit_pose(s, tee, 0.3, 1.5);
  EXPECT_FALSE(p.turned);
  EXPECT_TRUE(p.stance.identity());
  EXPECT_EQ(p.angle, 0.3);
  p = hit_pose(s, ball, 0.3, 1.5);
  EXPECT_FALSE(p.turned);
  EXPECT_EQ(p.stance, stance_for(s, ball, 0.0));
  // Beyond the envelope's angles, and at a negative angle faster than its capped club speed.
  for (const auto& [angle, speed] :
       {std::pair{c.angle_max + 0.3, 1.0}, std::pair{-1.2, 1.0}, std::pair{2.8, 2.0},
        std::pair{-0.2, s.module().club_speed_cap(-0.2) + 0.2}}) {
    p = hit_pose(s, ball, angle, speed);
    EXPECT_TRUE(p.turned) << angle;
    EXPECT_EQ(p.angle, 0.0) << angle;
    EXPECT_EQ(p.stance, stance_for(s, ball, angle)) << angle;
  }
  // Out of every stance's reach: no turn, the module refuses.
  EXPECT_FALSE(hit_reachable(s, 0.1, s.module().club_speed_cap() + 0.1));
  EXPECT_FALSE(hit_reachable(s, std::nan(""), 1.0));
  EXPECT_FALSE(hit_pose(s, ball, std::nan(""), 1.0).turned);
  EXPECT_FALSE(hit_pose(s, ball, 1.2, s.module().club_speed_cap() + 0.1).turned);
  EXPECT_TRUE(hit_reachable(s, -2.0, 1.0));
}

TEST(HitPose, AnArmHitLeavesAlongItsWorldAngleFromAnyStance) {
  const System s(load_config("", "flat"));
  SystemData d(s);
  const std::array<double, 2> ball{0.8, 0.2}, hole = s.field().hole.position;
  const auto fixed = arm_hit(s, d, {ball, hole}, 0.2, 0.6);
  ASSERT_TRUE(fixed.hit && !fixed.hit_refused);
  // The same bits as the fixed arm's putt within its reach.
  control::FullPuttOptions o;
  o.stance = stance_for(s, ball, 0.0);
  const auto same = arm_putt(s, d, hole, 0.2, 0.6, o);
  EXPECT_EQ(same.launch.angle, fixed.launch.angle);
  EXPECT_EQ(same.outcome.rest_position, fixed.outcome.rest_position);
  // Backwards and sideways: the base turns; the launch is a world angle near the request.
  for (const double angle : {1.3, -1.0, 2.9}) {
    const auto r = arm_hit(s, d, {ball, hole}, angle, 0.6);
    ASSERT_TRUE(r.hit && !r.hit_refused) << angle;
    EXPECT_NEAR(std::remainder(r.launch.angle - angle, 2 * M_PI), fixed.launch.angle - 0.2, 2e-3)
        << angle;
    const double dx = r.outcome.rest_position[0] - ball[0],
                 dy = r.outcome.rest_position[1] - ball[1];
    EXPECT_NEAR(std::remainder(std::atan2(dy, dx) - r.launch.angle, 2 * M_PI), 0.0, 0.02) << angle;
  }
  // NaN: refused, the ball untouched.
  EXPECT_TRUE(arm_hit(s, d, {ball, hole}, std::nan(""), 0.8).hit_refused);
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
