// What the learners read of a putt (system/observe.hpp): the launch read from a path, and the
// simulator's truth left exactly as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

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

}  // namespace
}  // namespace mg::system
