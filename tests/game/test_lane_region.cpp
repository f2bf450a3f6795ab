// The playable part of a lane: walls that meet the borders cut a part off; a ball there is out
// of play and goes back to the last point of its path in play.
#include "game/lane_region.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace mg::game {
namespace {

TEST(LaneRegion, TheCornerBehindTheLsWallsIsOutOfPlay) {
  const field::Field f = field::load_field("l-shape");
  const LaneRegion r(f, f.hole.position);
  EXPECT_TRUE(r.contains(f.tee));
  EXPECT_TRUE(r.contains(f.hole.position));
  EXPECT_TRUE(r.contains({2.2, 0.0}));    // the corridor's far end
  EXPECT_TRUE(r.contains({2.2, 1.7}));    // the leg to the hole
  EXPECT_FALSE(r.contains({0.5, 1.2}));   // behind the walls
  EXPECT_FALSE(r.contains({1.6, 0.75}));  // just behind the corner
  EXPECT_FALSE(r.contains({3.0, 0.0}));   // off the lane
  EXPECT_FALSE(r.contains({std::nan(""), 0.0}));
  // A resting ball touching a wall from the corridor side is in play.
  const double touch = 0.62 - 0.02 - f.ball.radius;
  EXPECT_TRUE(r.contains({1.0, touch}));
}

TEST(LaneRegion, AnOpenLaneIsInPlayEverywhereAroundBlocks) {
  const field::Field f = field::load_field("bank-shot");
  const LaneRegion r(f, f.hole.position);
  for (double x = -0.25; x < 2.69; x += 0.1)
    for (double y = -0.55; y < 0.59; y += 0.1) {
      const bool in_block = f.obstacles[0].distance({x, y}) < f.ball.radius;
      if (!in_block) {
        EXPECT_TRUE(r.contains({x, y})) << x << ", " << y;
      }
    }
}

TEST(LaneRegion, TheLastPointInPlayOfAPathThatHopsAWall) {
  const field::Field f = field::load_field("l-shape");
  const LaneRegion r(f, f.hole.position);
  std::vector<std::array<double, 2>> path;
  for (double y = 0.0; y <= 1.2; y += 0.01) path.push_back({1.0, y});
  const auto p = r.last_in_play(path, {9.0, 9.0});
  EXPECT_NEAR(p[0], 1.0, 1e-12);
  EXPECT_LT(p[1], 0.62 - 0.02);
  EXPECT_GT(p[1], 0.62 - 0.02 - f.ball.radius - 0.02);
  EXPECT_EQ(r.last_in_play({{0.5, 1.2}}, {9.0, 9.0}), (std::array<double, 2>{9.0, 9.0}));
}

}  // namespace
}  // namespace mg::game
