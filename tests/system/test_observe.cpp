// What the learners read of a putt (system/observe.hpp): the launch read from a path, and the
// simulator's truth left exactly as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "sim/fast_putt.hpp"
#include "system/observe.hpp"
#include "system/system.hpp"

namespace mg::system {
namespace {

TEST(Observe, TheLaunchIsReadFromThePathsFirstSamples) {
  // A ball slowing at a constant rate along 0.3 rad, sampled at 60 Hz from 1/60 s on.
  std::vector<sim::BallSample> path;
  const double c = std::cos(0.3), s = std::sin(0.3), v0 = 1.5, a = -2.0;
  for (int k = 1; k < 40; ++k) {
    const double t = k / 60.0, d = v0 * t + 0.5 * a * t * t, v = v0 + a * t;
    path.push_back({t, 0.1 + c * d, -0.2 + s * d, 0.02, c * v, s * v, 0.0});
  }
  const SeenLaunch l = launch_from_path(path, 0.02);
  ASSERT_TRUE(l.seen);
  const double v = v0 + a * 0.02, d = v0 * 0.02 + 0.5 * a * 0.02 * 0.02;
  EXPECT_NEAR(l.velocity[0], c * v, 1e-9);
  EXPECT_NEAR(l.velocity[1], s * v, 1e-9);
  EXPECT_NEAR(l.position[0], 0.1 + c * d, 1e-9);
  EXPECT_NEAR(l.position[1], -0.2 + s * d, 1e-9);
  // Too few samples in the window, or none in its first half: not seen (never made up).
  EXPECT_FALSE(launch_from_path({path[0], path[1]}, 0.02).seen);
  EXPECT_FALSE(launch_from_path({path.begin() + 11, path.end()}, 0.02).seen);
  EXPECT_FALSE(launch_from_path({}, 0.02).seen);
}

TEST(Observe, WithTheSimulatorsTruthAPuttIsLeftAsItWasBitForBit) {
  const System sys(load_config("", "flat"));
  ASSERT_FALSE(paths_seen_by_perception(sys));
  SystemData data(sys);
  control::FullPuttOptions o;
  o.record_interval = 0.005;
  o.rest_start = control::RestStart::kAtRestPose;
  const control::FullPuttResult played =
      arm_putt(sys, data, sys.field().hole.position, 0.0, 1.0, o);
  ASSERT_TRUE(played.hit);
  ASSERT_GT(played.outcome.trajectory.size(), 10u);
  control::FullPuttResult seen = played;
  perceive_putt(sys, data, seen);
  ASSERT_EQ(seen.outcome.trajectory.size(), played.outcome.trajectory.size());
  EXPECT_EQ(std::memcmp(seen.outcome.trajectory.data(), played.outcome.trajectory.data(),
                        sizeof(sim::BallSample) * played.outcome.trajectory.size()),
            0);
  EXPECT_EQ(std::memcmp(&seen.launch, &played.launch, sizeof(played.launch)), 0);
  EXPECT_EQ(std::memcmp(seen.launch_state.qpos.data(), played.launch_state.qpos.data(),
                        sizeof(played.launch_state.qpos)),
            0);
  EXPECT_EQ(std::memcmp(seen.launch_state.qvel.data(), played.launch_state.qvel.data(),
                        sizeof(played.launch_state.qvel)),
            0);
}

// The launch fitted to the roll: imagined as a plain slide from it (as the round's planner
// imagines the launch skill's putts), an arm putt's roll ends where it did; from the kinematic
// launch (the hop folded into a slide 3 % too fast) it ended 7-49 cm away (measured).
TEST(Observe, TheLaunchFittedToTheRollRollsWhereTheBallDid) {
  for (const char* name : {"flat", "regular-hill"}) {
    const System sys(load_config("", name));
    SystemData data(sys);
    control::FullPuttOptions o;
    o.record_interval = 0.01;
    const control::FullPuttResult r = arm_putt(sys, data, {2.5, -0.5}, 0.02, 1.4, o);
    ASSERT_TRUE(r.hit);
    const SeenLaunch kinematic = launch_from_path(r.outcome.trajectory, o.launch_delay);
    ASSERT_TRUE(kinematic.seen);
    const SeenLaunch fitted =
        fit_launch_to_roll(sys.ball_world(), r.outcome.trajectory, o.launch_delay, kinematic);
    EXPECT_EQ(fitted.position, kinematic.position);
    const auto rest_from = [&](const SeenLaunch& l) {
      sim::PuttRequest q;
      q.start = l.position;
      q.angle = std::atan2(l.velocity[1], l.velocity[0]);
      const auto g = sys.field().surface.gradient(l.position[0], l.position[1]);
      const double cz = g[0] * std::cos(q.angle) + g[1] * std::sin(q.angle);
      q.speed = std::hypot(l.velocity[0], l.velocity[1]) * std::sqrt(1.0 + cz * cz);
      const auto p = sim::fast_putt(sys.ball_world(), data.ball.get(), {2.5, -0.5}, q);
      return std::hypot(p.rest_position[0] - r.outcome.rest_position[0],
                        p.rest_position[1] - r.outcome.rest_position[1]);
    };
    EXPECT_GT(rest_from(kinematic), 0.15) << name;
    EXPECT_LT(rest_from(fitted), 0.04) << name;
    // Deterministic, and a launch not seen stays unseen.
    const SeenLaunch again =
        fit_launch_to_roll(sys.ball_world(), r.outcome.trajectory, o.launch_delay, kinematic);
    EXPECT_EQ(again.velocity, fitted.velocity);
    EXPECT_FALSE(fit_launch_to_roll(sys.ball_world(), r.outcome.trajectory, 0.02, {}).seen);
  }
}

// A roll heading along -x: the fit's turns cross +-pi and stay valid requests.
TEST(Observe, TheLaunchFitWrapsAHeadingNearPi) {
  const System sys(load_config("", "flat"));
  SystemData data(sys);
  sim::PuttRequest q;
  q.start = std::array<double, 2>{2.0, 0.0};
  q.angle = 3.1415;
  q.speed = 1.5;
  q.record_interval = 0.01;
  const auto p = sim::fast_putt(sys.ball_world(), data.ball.get(), {2.5, 0.4}, q);
  const SeenLaunch kinematic = launch_from_path(p.trajectory, 0.02);
  ASSERT_TRUE(kinematic.seen);
  const SeenLaunch fitted = fit_launch_to_roll(sys.ball_world(), p.trajectory, 0.02, kinematic);
  EXPECT_TRUE(fitted.seen);
  EXPECT_NEAR(std::abs(std::atan2(fitted.velocity[1], fitted.velocity[0])), 3.1415, 0.003);
}

}  // namespace
}  // namespace mg::system
