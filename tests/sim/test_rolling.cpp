// Ball physics against closed forms (PHYSICS.md): Penner's rolling, slide-then-roll, slopes.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "sim/putt.hpp"
#include "sim_test_util.hpp"

namespace mg::sim {
namespace {

constexpr double kG = 9.81;

TEST(Rolling, FlatDistanceAndStopTimeMatchPennerWithin3Percent) {
  const double rho = 0.131, mu = 0.3;
  const World world(testing::plane_field(0.0, 0.0, rho, 0.06, mu));
  auto d = world.make_data();
  for (double v0 : {0.8, 1.5, 2.3}) {
    PuttRequest q;
    q.speed = v0;
    const PuttOutcome out = simulate_putt(world, d.get(), world.field().hole.position, q);
    ASSERT_EQ(out.end, PuttEnd::kAtRest);
    // Slide without spin to (5/7) v0, then roll with deceleration (5/7) rho g.
    const double v1 = 5.0 / 7.0 * v0, a_roll = 5.0 / 7.0 * rho * kG;
    const double distance = 12.0 * v0 * v0 / (49.0 * mu * kG) + v1 * v1 / (2.0 * a_roll);
    const double time = 2.0 * v0 / (7.0 * mu * kG) + v1 / a_roll;
    const double measured_time = out.duration - OutcomeRules{}.rest_time;
    EXPECT_NEAR(out.rest_position[0], distance, 0.03 * distance) << "v0 " << v0;
    EXPECT_NEAR(measured_time, time, 0.03 * time) << "v0 " << v0;
    RecordProperty("distance_error_percent_v" + std::to_string(int(v0 * 10)),
                   std::to_string(100.0 * (out.rest_position[0] - distance) / distance));
  }
}

TEST(Rolling, SlideTurnsIntoRollAtTheClosedFormTimeWithin10Percent) {
  const double mu = 0.3;
  const World world(testing::plane_field(0.0, 0.0, 0.131, 0.06, mu));
  auto d = world.make_data();
  const double v0 = 2.0;
  PuttRequest q;
  q.speed = v0;
  q.record_interval = 0.001;
  const PuttOutcome out = simulate_putt(world, d.get(), world.field().hole.position, q);
  // The slide ends when the speed has fallen to the rolling speed (5/7) v0; after that it falls
  // only slowly (rolling resistance), so the first crossing of 0.5 % above it marks the end.
  double t_roll = -1.0, v_roll = 0.0;
  for (const auto& s : out.trajectory) {
    const double v = std::hypot(s.vx, s.vy);
    if (v <= 1.005 * 5.0 / 7.0 * v0) {
      t_roll = s.t;
      v_roll = v;
      break;
    }
  }
  const double t_star = 2.0 * v0 / (7.0 * mu * kG);
  EXPECT_NEAR(t_roll, t_star, 0.1 * t_star);
  EXPECT_NEAR(v_roll, 5.0 / 7.0 * v0, 0.03 * 5.0 / 7.0 * v0);
}

// Rolling ball (no resistance) on an incline: acceleration (5/7) g sin(slope) along the fall line.
TEST(Rolling, InclineAccelerationWithin3Percent) {
  for (const auto& [sx, sy] : {std::pair{0.05, 0.0}, std::pair{0.0, 0.08}, std::pair{0.1, 0.0}}) {
    const World world(testing::plane_field(sx, sy, 0.0));
    auto d = world.make_data();
    PuttRequest q;
    q.speed = 1.2;
    q.rolling_start = true;
    q.max_duration = 0.6;
    q.record_interval = 0.1;
    const PuttOutcome out = simulate_putt(world, d.get(), world.field().hole.position, q);
    const auto& a = out.trajectory[1];
    const auto& b = out.trajectory[5];
    const double dt = b.t - a.t;
    const double slope = std::atan(std::hypot(sx, sy));
    const double expected = 5.0 / 7.0 * kG * std::sin(slope);
    // Acceleration vector projected on the downhill direction (-grad), horizontal part.
    const double ax = (b.vx - a.vx) / dt, ay = (b.vy - a.vy) / dt, az = (b.vz - a.vz) / dt;
    const double g_norm = std::hypot(sx, sy);
    const double fall[3] = {-sx / g_norm * std::cos(slope), -sy / g_norm * std::cos(slope),
                            -std::sin(slope)};
    const double along = ax * fall[0] + ay * fall[1] + az * fall[2];
    EXPECT_NEAR(along, expected, 0.03 * expected) << sx << "," << sy;
  }
}

TEST(Rolling, StraightPuttOnTheFlatStaysOnItsLine) {
  const World world(field::load_field("flat"));
  auto d = world.make_data();
  for (double angle : {0.0, 0.25, -0.2}) {
    PuttRequest q;
    q.angle = angle;
    q.speed = 1.6;
    const PuttOutcome out = simulate_putt(world, d.get(), {2.5, 0.5}, q);
    const double off_line =
        -std::sin(angle) * out.rest_position[0] + std::cos(angle) * out.rest_position[1];
    EXPECT_LT(std::abs(off_line), 1e-4) << angle;
  }
}

TEST(Rolling, BallSentAtABorderComesBackIntoTheLane) {
  const World world(field::load_field("flat"));
  auto d = world.make_data();
  PuttRequest q;
  q.angle = 1.2;  // steeply at the +y border
  q.speed = 2.0;
  q.record_interval = 0.01;
  const PuttOutcome out = simulate_putt(world, d.get(), {2.5, -0.5}, q);
  double max_y = -1.0;
  bool came_back = false;
  for (const auto& s : out.trajectory) {
    max_y = std::max(max_y, s.y);
    came_back = came_back || s.vy < -0.1;
  }
  const auto& f = world.field();
  EXPECT_TRUE(came_back);
  EXPECT_LE(max_y, f.bounds[3] - 0.9 * f.ball.radius);
  EXPECT_LT(out.rest_position[1], f.bounds[3] - f.ball.radius);
  EXPECT_GT(out.rest_position[1], f.bounds[2]);
}

TEST(Rolling, SamePuttTwiceGivesIdenticalBits) {
  const World world(field::load_field("arctan"));
  auto d1 = world.make_data();
  auto d2 = world.make_data();
  PuttRequest q;
  q.angle = 0.15;
  q.speed = 2.1;
  q.record_interval = 0.01;
  const PuttOutcome a = simulate_putt(world, d1.get(), {2.1, 0.25}, q);
  simulate_putt(world, d2.get(), {1.0, 0.3}, q);  // dirty the second data first
  const PuttOutcome b = simulate_putt(world, d2.get(), {2.1, 0.25}, q);
  ASSERT_EQ(a.trajectory.size(), b.trajectory.size());
  EXPECT_EQ(0, std::memcmp(a.trajectory.data(), b.trajectory.data(),
                           a.trajectory.size() * sizeof(BallSample)));
  EXPECT_EQ(a.closest_approach, b.closest_approach);
  EXPECT_EQ(a.steps, b.steps);
}

TEST(Rolling, BadRequestsAreErrors) {
  const World world(field::load_field("flat"));
  auto d = world.make_data();
  PuttRequest q;
  q.speed = NAN;
  EXPECT_THROW(simulate_putt(world, d.get(), {2.0, 0.0}, q), InputError);
  q.speed = -1.0;
  EXPECT_THROW(simulate_putt(world, d.get(), {2.0, 0.0}, q), InputError);
  q.speed = 1.0;
  q.angle = INFINITY;
  EXPECT_THROW(simulate_putt(world, d.get(), {2.0, 0.0}, q), InputError);
  q.angle = 0.0;
  q.start = std::array<double, 2>{5.0, 0.0};
  EXPECT_THROW(simulate_putt(world, d.get(), {2.0, 0.0}, q), InputError);
}

}  // namespace
}  // namespace mg::sim
