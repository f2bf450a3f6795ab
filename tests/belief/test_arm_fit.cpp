// Arm identification over numbers: robust means, their standard errors, the launch direction.
#include "belief/arm_fit.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg::belief {
namespace {

TEST(RobustMean, IsTheMeanOfCleanDataWithItsStandardError) {
  const auto m = robust_mean({1.0, 2.0, 3.0, 4.0});
  EXPECT_NEAR(m[0], 2.5, 1e-12);
  EXPECT_NEAR(m[1], std::sqrt(5.0 / 3.0 / 4.0), 1e-12);  // sample std / sqrt(n)
}

TEST(RobustMean, AnOutlierDoesNotCarryIt) {
  const auto m = robust_mean({0.97, 0.971, 0.969, 0.972, 0.968, 1.5});
  EXPECT_NEAR(m[0], 0.97, 0.002);
  EXPECT_LT(m[1], 0.01);
}

TEST(RobustMean, OneValueHasNoStandardError) {
  EXPECT_EQ(robust_mean({0.3})[0], 0.3);
  EXPECT_TRUE(std::isinf(robust_mean({0.3})[1]));
  EXPECT_TRUE(std::isinf(robust_mean({})[1]));
}

TEST(FitArm, ScaleFromReachedOverPredictedAndBiasFromAngles) {
  std::vector<ArmObservation> obs;
  const double bias = -0.003;
  for (int i = 0; i < 6; ++i) {
    ArmObservation o;
    o.commanded_speed = 1.0 + 0.1 * i;
    o.predicted_speed = 0.98 * o.commanded_speed;  // the model's own tracking
    o.reached_speed = 0.95 * o.predicted_speed * (1.0 + 1e-3 * (i % 2 ? 1 : -1));
    o.predicted_launch_angle = 0.1 * i - 0.2;
    o.observed_launch_angle = o.predicted_launch_angle + bias + 2e-4 * (i % 3 - 1);
    obs.push_back(o);
  }
  ArmObservation no_angle;
  no_angle.commanded_speed = 1.2;
  no_angle.reached_speed = 1.14;  // predicted 0: against the command
  obs.push_back(no_angle);
  const ArmEstimate e = fit_arm(obs);
  EXPECT_EQ(e.speed_observations, 7);
  EXPECT_EQ(e.angle_observations, 6);
  EXPECT_NEAR(e.club_speed_scale, 0.95, 1e-3);
  EXPECT_NEAR(e.launch_angle_bias, bias, 1e-4);
  EXPECT_GT(e.launch_angle_bias_std, 0.0);
  EXPECT_LT(e.launch_angle_bias_std, 2e-4);
  ArmObservation bad;
  bad.commanded_speed = -1.0;
  EXPECT_THROW(fit_arm({bad}), InputError);
  const ArmEstimate none = fit_arm({});
  EXPECT_EQ(none.club_speed_scale, 1.0);
  EXPECT_TRUE(std::isinf(none.launch_angle_bias_std));
}

TEST(PathDirection, IsTheLinesAngleTheWayTheBallWent) {
  std::vector<std::array<double, 3>> s;
  const double angle = 2.9;  // backwards and to the left
  for (int i = 0; i < 50; ++i) {
    const double d = 0.02 * i;
    s.push_back({0.01 * i, 1.0 + d * std::cos(angle), 0.2 + d * std::sin(angle)});
  }
  EXPECT_NEAR(path_direction(s, 0.0, 1.0), angle, 1e-12);
  EXPECT_NEAR(path_direction(s, 0.1, 0.3), angle, 1e-12);
  EXPECT_TRUE(std::isnan(path_direction(s, 0.0, 0.015)));  // 2 samples
}

}  // namespace
}  // namespace mg::belief
