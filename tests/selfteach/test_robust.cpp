// Noise-aware arrival speed: the Monte Carlo sink probability against closed forms and limits.
#include "selfteach/robust.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "field/field.hpp"

namespace mg::selfteach {
namespace {

const field::Field& flat() {
  static const field::Field f = field::load_field("flat");
  return f;
}

TEST(Robust, WithoutNoiseEveryArrivalBelowTheCaptureSpeedSinks) {
  const LaunchNoise none;
  EXPECT_EQ(sink_probability(flat(), 2.0, 0.4, none), 1.0);
  EXPECT_EQ(sink_probability(flat(), 2.0, 1.5, none), 1.0);
  EXPECT_EQ(sink_probability(flat(), 2.0, 2.0, none), 0.0);  // above the 1.69 m/s lip-out
}

TEST(Robust, AlongTheLineNoiseMatchesTheClosedForm) {
  // Only the hole's position along the line is uncertain (lateral draws are independent of it,
  // so use a noise whose lateral part cannot miss: a 1 mm std against a 54 mm radius).
  LaunchNoise n;
  n.position_std = 0.001;
  const auto& f = flat();
  const double a = 5.0 / 7.0 * f.rolling_resistance * 9.81, s = 0.1;
  const double sd = 2.0 * a * std::sqrt(2.0) * n.position_std;  // std of 2 a e_along
  const double lo = -2.0 * a * (0.5 * f.hole.diameter - f.ball.radius) - s * s;
  const auto phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  const double closed = 1.0 - phi(lo / sd);  // the upper bound (capture) is far away
  EXPECT_NEAR(sink_probability(f, 2.0, s, n, 20000), closed, 0.01);
}

TEST(Robust, SpeedNoiseAsksForAFasterArrivalAndLateralNoiseForASlowOne) {
  LaunchNoise speed;
  speed.speed_rel_std = 0.03;
  LaunchNoise lateral;
  lateral.angle_std = 0.012;
  field::Situations region = flat().situations;
  const double fast = robust_arrival_speed(flat(), region, speed);
  const double slow = robust_arrival_speed(flat(), region, lateral);
  EXPECT_GT(fast, 0.6);
  EXPECT_LT(slow, 0.45);
  EXPECT_GT(sink_probability(flat(), 2.0, fast, speed),
            sink_probability(flat(), 2.0, 0.4, speed) + 0.05);
}

}  // namespace
}  // namespace mg::selfteach
