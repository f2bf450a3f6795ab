#include "belief/prior.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "field/field.hpp"
#include "plant/plant.hpp"

namespace mg::belief {
namespace {

TEST(Prior, LaunchAndArrivalAreInverse) {
  const field::Field f = field::load_field("regular-hill");
  for (const double arrival : {0.3, 0.6, 1.0}) {
    const std::array<double, 2> hole{2.0, 0.2};
    const LaunchGuess g = prior_launch(f, f.tee, hole, arrival);
    EXPECT_NEAR(prior_arrival(f, f.tee, hole, g.speed), arrival, 1e-12);
  }
  // A launch too slow to arrive arrives at 0, never at a negative or NaN speed.
  EXPECT_EQ(prior_arrival(f, f.tee, {2.0, 0.0}, 0.1), 0.0);
}

TEST(Prior, RollingDecelerationIsPenners) {
  field::Field f = field::load_field("flat");
  f.rolling_resistance = 0.2;
  EXPECT_DOUBLE_EQ(rolling_deceleration(f), 5.0 / 7.0 * 0.2 * 9.81);
}

TEST(Prior, SameGreenAndArmKeepTheSpeedBitForBit) {
  const field::Field f = field::load_field("flat");
  for (const double v : {1.2, 1.55, 1.9})
    EXPECT_EQ(equivalent_club_speed(v, f, f, 1.0, f.tee, {2.0, 0.1}), v);
}

TEST(Prior, EquivalentSpeedKeepsTheArrivalSpeed) {
  const field::Field surveyed = field::load_field("flat");
  plant::Plant p;
  p.field.rolling_resistance_scale = 1.12;
  p.field.extra_slope = {0.002, -0.0015};
  const field::Field slower = plant::true_field(surveyed, p);
  const std::array<double, 2> hole{1.0, 0.1};  // near enough that the prior's ball arrives
  constexpr double kRatio = 1.6, kScale = 0.97;
  ASSERT_GT(prior_arrival(surveyed, surveyed.tee, hole, kRatio * 1.55), 0.3);
  const double v = equivalent_club_speed(1.55, surveyed, slower, kScale, surveyed.tee, hole);
  EXPECT_GT(v, 1.55 / kScale);  // a slower green and a weaker arm: a harder hit
  EXPECT_NEAR(prior_arrival(slower, surveyed.tee, hole, kRatio * kScale * v),
              prior_arrival(surveyed, surveyed.tee, hole, kRatio * 1.55), 1e-9);
  // Only the arm differs: the club speed scales by exactly its inverse.
  EXPECT_NEAR(equivalent_club_speed(1.55, surveyed, surveyed, kScale, surveyed.tee, hole),
              1.55 / kScale, 1e-15);
}

}  // namespace
}  // namespace mg::belief
