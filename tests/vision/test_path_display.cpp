// The ball's whole roll as the cameras saw it (vision/path_observer.hpp, system/observe.hpp).
// Rendering tests need a display (ctest runs them under xvfb-run as vision_under_xvfb); small
// images (320 x 240) keep them fast.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../viz/viz_test_util.hpp"
#include "small_rig.hpp"
#include "system/observe.hpp"
#include "system/system.hpp"
#include "vision/camera_perception.hpp"
#include "vision/path_observer.hpp"
#include "viz/renderer.hpp"

namespace mg::vision {
namespace {

using testing::small_rig;

/// The recorded path at `t` (linear between its samples: they are 5 ms apart).
Eigen::Vector3d truth_at(const std::vector<sim::BallSample>& path, double t) {
  const auto b = std::lower_bound(path.begin(), path.end(), t,
                                  [](const sim::BallSample& s, double v) { return s.t < v; });
  if (b == path.begin()) return {b->x, b->y, b->z};
  if (b == path.end()) return {path.back().x, path.back().y, path.back().z};
  const auto& a = *(b - 1);
  const double u = (t - a.t) / (b->t - a.t);
  return {a.x + u * (b->x - a.x), a.y + u * (b->y - a.y), a.z + u * (b->z - a.z)};
}

TEST(PathObserver, LostFramesGiveNoSamplesAndNothingIsFilledIn) {
  // Frames at 60 Hz of a ball moving at (1, 0.5) m/s; the contact at 0.1 s; lost 0.5-0.7 s.
  std::vector<PathFrame> frames;
  for (int k = 0; k < 60; ++k) {
    PathFrame f;
    f.stamp = k / 60.0;
    const double t = std::max(0.0, f.stamp - 0.1);
    f.point = {0.2 + t, 0.1 + 0.5 * t, 0.02};
    const bool lost = f.stamp > 0.5 && f.stamp < 0.7;
    f.views = lost ? 0 : 2;
    f.accepted = !lost;
    frames.push_back(f);
  }
  const auto path = path_samples(frames, 0.1);
  ASSERT_FALSE(path.empty());
  EXPECT_GE(path.front().t, -1e-9);  // nothing before the contact
  for (const auto& s : path) {
    EXPECT_FALSE(s.t + 0.1 > 0.5 && s.t + 0.1 < 0.7) << s.t;
    EXPECT_NEAR(s.x, 0.2 + s.t, 1e-9);
    EXPECT_NEAR(s.vx, 1.0, 1e-6);
    EXPECT_NEAR(s.vy, 0.5, 1e-6);
  }
  // One sample per accepted frame from the contact on.
  const auto accepted = std::count_if(frames.begin(), frames.end(), [](const PathFrame& f) {
    return f.accepted && f.stamp >= 0.1 - 1e-9;
  });
  EXPECT_EQ(static_cast<long>(path.size()), accepted);
}

TEST(PathDisplay, TheCamerasSeeTheWholeRollWithinMillimetres) {
  MG_NEED_DISPLAY();
  const Rig rig = small_rig();
  const system::System sys(system::load_config("", "flat"), {}, {},
                           camera_perception(Cameras{rig, exact_calibration(rig)}));
  ASSERT_TRUE(system::paths_seen_by_perception(sys));
  system::SystemData data(sys);
  control::FullPuttOptions o;
  o.record_interval = 0.005;
  o.rest_start = control::RestStart::kAtRestPose;
  control::FullPuttResult r = system::arm_putt(sys, data, sys.field().hole.position, 0.1, 0.8, o);
  ASSERT_TRUE(r.hit);
  ASSERT_TRUE(r.handed_off);
  const auto truth = r.outcome.trajectory;
  const auto launch = r.launch;
  system::perceive_putt(sys, data, r);
  const auto& seen = r.outcome.trajectory;
  ASSERT_GT(seen.size(), 20u);
  // At the rig's rate, over the whole roll: after the hand-off to its end.
  EXPECT_GT(seen.back().t, r.handoff_time + 0.5);
  EXPECT_GT(seen.back().t, truth.back().t - 0.2);
  double worst = 0.0;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    // The module's frames are taken at its perception ticks (10 ms), the roll's at the rig's.
    if (i > 0 && seen[i - 1].t > r.handoff_time) {
      const double gap = (seen[i].t - seen[i - 1].t) * 60.0;
      EXPECT_NEAR(gap, std::round(gap), 1e-6);  // whole frames apart
    }
    worst = std::max(worst,
                     (Eigen::Vector3d(seen[i].x, seen[i].y, seen[i].z) - truth_at(truth, seen[i].t))
                         .head<2>()
                         .norm());
  }
  EXPECT_LT(worst, 0.004);
  // The launch read from the path: its direction within a few mrad of the simulator's; its speed
  // that of the plain sliding launch that continues into the roll seen (the ball hops off the
  // club and lands where the cameras do not use it: up to 10 % from the speed in the air).
  EXPECT_NEAR(r.launch.angle, launch.angle, 0.006);
  EXPECT_NEAR(r.launch.speed / launch.speed, 1.0, 0.12);
}

TEST(PathDisplay, ABallOutOfSightGivesMissingSamplesNotInventedOnes) {
  MG_NEED_DISPLAY();
  const system::System sys(system::load_config("", "flat"));
  const Rig rig = small_rig();
  viz::GlWindow window(64, 64, false, "test");
  RigRenderer renderer(sys.ball_world(), rig);
  auto d = sys.ball_world().make_data();
  const StereoModel model(exact_calibration(rig), sys.field());
  // A ball rolling along the lane at 1 m/s for 1 s, taken off it (below the lane) from 0.4 to
  // 0.6 s.
  const double z = sys.field().ball.radius + sys.field().height(0.5, 0.0);
  std::vector<sim::BallSample> path;
  for (int k = 0; k <= 200; ++k) {
    const double t = k * 0.005;
    const bool away = t > 0.4 && t < 0.6;
    path.push_back({t, 0.5 + t, 0.0, away ? -1.0 : z, 1.0, 0.0, 0.0});
  }
  StereoData data(model);
  std::vector<PathFrame> frames;
  const RollStats st = watch_roll(renderer, d.get(), model, data, path, 0.0,
                                  sys.field().hole.position, 0.0, 1.0 / 60.0, frames);
  EXPECT_EQ(st.frames, 61);
  EXPECT_GE(st.lost, 10);
  const auto seen = path_samples(frames, 0.0);
  ASSERT_GT(seen.size(), 30u);
  for (const auto& s : seen) {
    EXPECT_FALSE(s.t > 0.41 && s.t < 0.59) << s.t;
    EXPECT_NEAR(s.x, 0.5 + s.t, 0.004) << s.t;
  }
}

}  // namespace
}  // namespace mg::vision
