// Capture at the hole: a slow ball drops in, a fast one lips out (PHYSICS.md v_cap(b)).
#include <cmath>

#include <gtest/gtest.h>

#include "sim/putt.hpp"
#include "sim_test_util.hpp"

namespace mg::sim {
namespace {

constexpr double kG = 9.81;
const std::array<double, 2> kHole{1.5, 0.0};

// The free-fall capture speed for a path offset b from the hole centre.
double v_cap(const field::Field& f, double b) {
  const double R = 0.5 * f.hole.diameter, r = f.ball.radius;
  return (2.0 * std::sqrt(R * R - b * b) - r) * std::sqrt(kG / (2.0 * r));
}

// Rolls the ball at `speed` across the hole on a path offset `b`, from just before the rim.
bool sinks(const World& world, mjData* d, double b, double speed) {
  PuttRequest q;
  q.speed = speed;
  q.rolling_start = true;
  const double radius = 0.5 * world.field().hole.diameter;
  const double rim = radius > std::abs(b) ? std::sqrt(radius * radius - b * b) : 0.0;
  q.start = std::array<double, 2>{kHole[0] - rim - 0.002, kHole[1] + b};
  q.max_duration = 1.0;  // decide before a rebound from the far border could come back
  return simulate_putt(world, d, kHole, q).sunk;
}

// Highest speed (0.05 m/s steps) below which every tried speed sinks.
double capture_speed(const World& world, mjData* d, double b) {
  double v = 0.1;
  while (v < 4.0 && sinks(world, d, b, v + 0.05)) v += 0.05;
  return v;
}

TEST(Hole, SlowCentredBallDropsFastOneLipsOut) {
  const World world(testing::plane_field());
  auto d = world.make_data();
  EXPECT_TRUE(sinks(world, d.get(), 0.0, 0.4));
  EXPECT_TRUE(sinks(world, d.get(), 0.0, 0.9 * v_cap(world.field(), 0.0)));
  EXPECT_FALSE(sinks(world, d.get(), 0.0, 2.0 * v_cap(world.field(), 0.0)));
}

TEST(Hole, CaptureWindowShrinksWithOffsetAndTracksTheFreeFallSpeed) {
  const World world(testing::plane_field());
  auto d = world.make_data();
  double previous = 1e9;
  for (double b : {0.0, 0.02, 0.035, 0.045}) {
    const double measured = capture_speed(world, d.get(), b);
    const double formula = v_cap(world.field(), b);
    RecordProperty("capture_speed_b" + std::to_string(int(b * 1000)), std::to_string(measured));
    EXPECT_LT(measured, previous) << "offset " << b;
    // The geometric cup with a rolling ball captures somewhat above the free-fall bound
    // (docs/physics.md lists the measured ratios); it must stay within [0.8, 1.7] of it.
    EXPECT_GT(measured, 0.8 * formula) << "offset " << b;
    EXPECT_LT(measured, 1.7 * formula) << "offset " << b;
    previous = measured;
  }
  // A path that misses the cup never drops.
  EXPECT_FALSE(sinks(world, d.get(), 0.5 * world.field().hole.diameter + 0.003, 0.3));
}

TEST(Hole, ShallowHoleCapturesOnlySlowerBalls) {
  const World deep(testing::plane_field(0.0, 0.0, 0.131, 0.06));
  const World shallow(testing::plane_field(0.0, 0.0, 0.131, 0.01));
  auto dd = deep.make_data();
  auto ds = shallow.make_data();
  const double v_deep = capture_speed(deep, dd.get(), 0.0);
  const double v_shallow = capture_speed(shallow, ds.get(), 0.0);
  EXPECT_LT(v_shallow, 0.8 * v_deep);
  EXPECT_TRUE(sinks(shallow, ds.get(), 0.0, 0.3));
}

TEST(Hole, AimedPuttSinksOnEveryShippedField) {
  // A slow straight putt rolled from near the hole along the fall line finds the cup.
  for (const char* name : {"flat", "multiple-hills", "regular-hill", "arctan"}) {
    const World world(field::load_field(name));
    auto d = world.make_data();
    const auto h = world.field().hole.position;
    PuttRequest q;
    q.speed = 0.3;
    q.rolling_start = true;
    q.start = std::array<double, 2>{h[0] - 0.08, h[1]};
    q.max_duration = 3.0;
    EXPECT_TRUE(simulate_putt(world, d.get(), h, q).sunk) << name;
  }
}

}  // namespace
}  // namespace mg::sim
