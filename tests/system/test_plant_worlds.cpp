// Belief and truth: the worlds of a System with a plant (plant/plant.hpp), checked against the
// identity, closed forms and the parts of the robot that must not see the plant.
#include <cmath>

#include <gtest/gtest.h>

#include "plant/plant.hpp"
#include "system/parallel.hpp"
#include "system/system.hpp"

namespace mg::system {
namespace {

constexpr double kG = 9.81;

/// A plant file of `yaml` after its version line.
plant::Plant plant_of(const std::string& yaml) {
  return plant::parse_plant("format_version: 1\n" + yaml, "test plant");
}

double distance(const sim::PuttOutcome& o, std::array<double, 2> from) {
  return std::hypot(o.rest_position[0] - from[0], o.rest_position[1] - from[1]);
}

TEST(PlantWorlds, AnEmptyPlantChangesNoBit) {
  const auto config = load_config("", "regular-hill");
  const System nominal(config);
  const System empty(config, plant_of(""));
  SystemData a(nominal), b(empty);
  const std::array<double, 2> hole{2.1, 0.05};
  const auto ra = arm_putt(nominal, a, hole, 0.02, 1.7, {});
  const auto rb = arm_putt(empty, b, hole, 0.02, 1.7, {});
  EXPECT_EQ(ra.outcome.rest_position, rb.outcome.rest_position);
  EXPECT_EQ(ra.outcome.closest_approach, rb.outcome.closest_approach);
  EXPECT_EQ(ra.launch.angle, rb.launch.angle);
  EXPECT_EQ(ra.launch.speed, rb.launch.speed);
  EXPECT_EQ(ra.club.speed, rb.club.speed);
  EXPECT_EQ(ra.outcome.steps, rb.outcome.steps);
  const auto ba = ball_putt(nominal, a, hole, 0.01, 2.0), bb = ball_putt(empty, b, hole, 0.01, 2.0);
  EXPECT_EQ(ba.rest_position, bb.rest_position);
  EXPECT_EQ(ba.steps, bb.steps);
  EXPECT_EQ(nominal.arm_world().mjcf(), empty.arm_world().mjcf());
}

TEST(PlantWorlds, TheRobotsModelNeverSeesThePlant) {
  const auto config = load_config("", "flat");
  const System nominal(config);
  const System real(config,
                    plant_of(R"(field: {rolling_resistance_scale: 1.2, extra_slope: [0.004, 0.0]}
arm: {joint_friction: [1, 1, 0.5, 0.5, 0.05, 0.05, 0.01], club_restitution_scale: 0.9})"));
  EXPECT_EQ(real.field().rolling_resistance, nominal.field().rolling_resistance);
  EXPECT_EQ(real.field().surface.terms.size(), nominal.field().surface.terms.size());
  EXPECT_DOUBLE_EQ(real.arm_world().field().rolling_resistance,
                   1.2 * nominal.field().rolling_resistance);
  EXPECT_EQ(real.module().arm().damping(), nominal.module().arm().damping());
  EXPECT_EQ(real.module().ball_radius(), nominal.module().ball_radius());
  EXPECT_NE(real.arm_world().mjcf().find("frictionloss"), std::string::npos);
  EXPECT_EQ(nominal.arm_world().mjcf().find("frictionloss"), std::string::npos);
  // The arm still hits, within its limits, through its friction.
  SystemData d(real);
  const auto r = arm_putt(real, d, {2.0, 0.0}, 0.0, 1.6);
  ASSERT_TRUE(r.hit);
  EXPECT_LE(r.max_torque_ratio, 1.0);
  EXPECT_LE(r.max_velocity_ratio, 1.0);
  EXPECT_GT(r.min_position_margin, 0.0);
}

TEST(PlantWorlds, SlowerGrassShortensTheRollAsPennersLawSays) {
  // Ball only, launched sliding at v0 on the level flat field: it slides to v0 5/7 (distance
  // (v0^2 - (5/7 v0)^2) / (2 mu g), as in physics tests), then rolls (5/7 v0)^2 / (2 (5/7) rho g).
  const auto config = load_config("", "flat");
  const System nominal(config);
  const System slow(config, plant_of("field: {rolling_resistance_scale: 1.25}\n"));
  SystemData a(nominal), b(slow);
  const std::array<double, 2> far_hole{2.5, 0.5};  // off the path
  const double v0 = 1.5;
  const auto on = ball_putt(nominal, a, far_hole, 0.0, v0),
             os = ball_putt(slow, b, far_hole, 0.0, v0);
  const auto& f = nominal.field();
  const double v1 = 5.0 / 7.0 * v0;
  const double slide = (v0 * v0 - v1 * v1) / (2.0 * f.sliding_friction * kG);
  const double roll_nominal = distance(on, f.tee) - slide, roll_slow = distance(os, f.tee) - slide;
  EXPECT_NEAR(roll_nominal / roll_slow, 1.25, 0.03);
  EXPECT_NEAR(roll_slow, v1 * v1 / (2.0 * 5.0 / 7.0 * 1.25 * f.rolling_resistance * kG),
              0.03 * roll_slow);
}

TEST(PlantWorlds, AMissedTiltBendsTheRollDownhill) {
  const auto config = load_config("", "flat");
  const System tilted(config, plant_of("field: {extra_slope: [0.0, 0.004]}\n"));
  SystemData d(tilted);
  const auto o = ball_putt(tilted, d, {2.5, 0.5}, 0.0, 1.5);
  EXPECT_LT(o.rest_position[1], -0.01);  // z grows with y: downhill is -y
}

TEST(PlantWorlds, TheHoleIsWhereThePlantPutsIt) {
  const auto config = load_config("", "flat");
  const System nominal(config);
  const System offset(config, plant_of("field: {hole_offset: [0.0, 0.09]}\n"));
  EXPECT_EQ(real_hole(nominal, {2.0, 0.1}), (std::array<double, 2>{2.0, 0.1}));
  const auto h = real_hole(offset, {2.0, 0.1});
  EXPECT_DOUBLE_EQ(h[0], 2.0);
  EXPECT_DOUBLE_EQ(h[1], 0.1 + 0.09);
  // A ball-only putt that sinks the seen hole misses the real one.
  SystemData a(nominal), b(offset);
  int sunk_nominal = 0, sunk_offset = 0;
  for (double v = 2.2; v <= 3.4; v += 0.05) {
    const bool s = ball_putt(nominal, a, {2.0, 0.0}, 0.0, v).sunk;
    sunk_nominal += s;
    if (s) sunk_offset += ball_putt(offset, b, {2.0, 0.0}, 0.0, v).sunk;
  }
  EXPECT_GT(sunk_nominal, 0);
  EXPECT_EQ(sunk_offset, 0);
}

TEST(PlantWorlds, TheLaunchBiasAndTheSlowerArmShowInTheMeasuredLaunch) {
  const auto config = load_config("", "flat");
  const System nominal(config);
  const System biased(config, plant_of("arm: {launch_angle_bias: 0.004}\n"));
  const System slower(config, plant_of("arm: {club_speed_scale: 0.95}\n"));
  SystemData a(nominal), b(biased), c(slower);
  const auto rn = arm_putt(nominal, a, {2.0, 0.0}, 0.01, 1.6);
  const auto rb = arm_putt(biased, b, {2.0, 0.0}, 0.01, 1.6);
  const auto rs = arm_putt(slower, c, {2.0, 0.0}, 0.01, 1.6);
  ASSERT_TRUE(rn.hit && rb.hit && rs.hit);
  EXPECT_NEAR(rb.launch.angle - rn.launch.angle, 0.004, 1e-4);
  EXPECT_NEAR(rb.launch.speed, rn.launch.speed, 1e-3 * rn.launch.speed);
  EXPECT_NEAR(rs.club.speed / rn.club.speed, 0.95, 0.01);
  EXPECT_NEAR(rs.launch.speed / rn.launch.speed, 0.95, 0.015);
}

TEST(PlantWorlds, LateAndNoisyVisionStillHitsAndIsDeterministic) {
  const auto config = load_config("", "flat");
  const System nominal(config);
  const System seeing(config, plant_of("perception: {noise: 0.004, latency: 0.03}\n"));
  SystemData a(nominal), b(seeing);
  const auto rn = arm_putt(nominal, a, {2.0, 0.0}, 0.01, 1.6);
  const auto rv = arm_putt(seeing, b, {2.0, 0.0}, 0.01, 1.6);
  ASSERT_TRUE(rv.hit);
  EXPECT_NE(rv.outcome.rest_position, rn.outcome.rest_position);  // the club met the ball elsewhere
  // The same bits on any thread, with a fresh or a used scratch.
  std::vector<std::array<double, 2>> serial(3), parallel(3);
  for (int i = 0; i < 3; ++i)
    serial[static_cast<std::size_t>(i)] =
        arm_putt(seeing, b, {2.0, 0.1 * i}, 0.01 * i, 1.6).outcome.rest_position;
  parallel_for(seeing, 3, 2, [&](int i, SystemData& data) {
    parallel[static_cast<std::size_t>(i)] =
        arm_putt(seeing, data, {2.0, 0.1 * i}, 0.01 * i, 1.6).outcome.rest_position;
  });
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace mg::system
