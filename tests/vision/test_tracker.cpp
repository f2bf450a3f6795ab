// The ball's filter: follows a rolling ball and learns its velocity, refuses an outlier,
// restarts after three in a row (a struck ball), and a prediction is no measurement.
#include <gtest/gtest.h>

#include <random>

#include "vision/tracker.hpp"

namespace mg::vision {
namespace {

TEST(Tracker, FollowsARollingBallAndRefusesAnOutlier) {
  TrackerConfig c;
  Track k;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 0.001);
  const Eigen::Vector2d v(1.2, -0.3);
  for (int i = 0; i < 60; ++i) {
    const double t = i / 60.0;
    const Eigen::Vector2d z = v * t + Eigen::Vector2d(noise(rng), noise(rng));
    EXPECT_TRUE(track_update(k, c, t, z, 0.001)) << i;
  }
  EXPECT_NEAR(k.x[2], 1.2, 0.1);
  EXPECT_NEAR(k.x[3], -0.3, 0.1);
  EXPECT_LT((k.x.head<2>() - v * (59 / 60.0)).norm(), 0.002);
  // A wild measurement (another white blob half a metre away) is refused, the state kept.
  const Eigen::Vector2d before = k.x.head<2>();
  EXPECT_FALSE(track_update(k, c, 1.0, v + Eigen::Vector2d(0.5, 0.0), 0.001));
  EXPECT_EQ(k.rejected, 1);
  EXPECT_EQ(k.last_measured, 59 / 60.0);            // a refused measurement is no measurement
  EXPECT_GT((k.x.head<2>() - before).norm(), 0.0);  // (predicted on to t = 1)
  EXPECT_TRUE(track_update(k, c, 1.05, v * 1.05, 0.001));  // back on track: the count resets
  // Prediction alone moves the state but never the time of the last measurement.
  track_predict(k, c, 1.1);
  EXPECT_EQ(k.last_measured, 1.05);
  // Three outliers in a row: the ball really is there now (struck); the track restarts.
  EXPECT_FALSE(track_update(k, c, 1.2, Eigen::Vector2d(0.0, 0.5), 0.001));
  EXPECT_FALSE(track_update(k, c, 1.3, Eigen::Vector2d(0.0, 0.5), 0.001));
  EXPECT_TRUE(track_update(k, c, 1.4, Eigen::Vector2d(0.0, 0.5), 0.001));
  EXPECT_EQ(k.x.head<2>(), Eigen::Vector2d(0.0, 0.5));
  EXPECT_EQ(k.last_measured, 1.4);
}

}  // namespace
}  // namespace mg::vision
