// The true world's effects as wrappers: each one's effect on its own, identity wrappers that give
// the bits of none, and the harness asking them whether the arm and the vision are ideal.
#include "sim_backend/plant_effects.hpp"

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "field/field.hpp"
#include "sim_backend/full_system.hpp"

namespace mg::testing {
long allocations();  // count_allocations.cpp counts operator new
}  // namespace mg::testing

namespace mg::control {
namespace {

struct Rig {
  sim::World world{make_world_with_arm(field::load_field("flat"))};
  sim::World ball_world{make_ball_world(world)};
  ModuleModel model{make_module_model(world,
                                      ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                                             "/data/models/hitting-default.json"),
                                      ModuleConfig{})};
  sim::DataPtr data{world.make_data()};
  FullPuttResult putt(double angle, double speed, const FullPuttOptions& options,
                      PuttScratch* scratch = nullptr, const PlantEffects& effects = {}) {
    return full_system_putt(world, model, data.get(), {2.0, 0.0}, angle, speed, options, scratch,
                            effects);
  }
  FullPuttOptions handoff(RestStart start = RestStart::kApproach) const {
    FullPuttOptions o;
    o.ball_world = &ball_world;
    o.rest_start = start;
    return o;
  }
};

Rig& rig() {
  static Rig r;
  return r;
}

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// `steps`: also the simulated steps (not for a putt whose approach came from the cache).
void expect_same_bits(const FullPuttResult& a, const FullPuttResult& b, const std::string& what,
                      bool steps = true) {
  EXPECT_EQ(a.hit, b.hit) << what;
  EXPECT_TRUE(same(a.outcome.rest_position[0], b.outcome.rest_position[0])) << what;
  EXPECT_TRUE(same(a.outcome.rest_position[1], b.outcome.rest_position[1])) << what;
  EXPECT_TRUE(same(a.outcome.closest_approach, b.outcome.closest_approach)) << what;
  EXPECT_TRUE(same(a.outcome.duration, b.outcome.duration)) << what;
  EXPECT_EQ(a.outcome.steps, b.outcome.steps) << what;
  EXPECT_TRUE(same(a.launch.angle, b.launch.angle)) << what;
  EXPECT_TRUE(same(a.launch.speed, b.launch.speed)) << what;
  EXPECT_TRUE(same(a.club.angle, b.club.angle)) << what;
  EXPECT_TRUE(same(a.club.speed, b.club.speed)) << what;
  EXPECT_TRUE(same(a.rest_time, b.rest_time)) << what;
  EXPECT_TRUE(same(a.hit_detection_lag, b.hit_detection_lag)) << what;
  if (steps) EXPECT_EQ(a.arm_steps, b.arm_steps) << what;
}

TEST(PlantEffects, IdentityWrappersGiveTheBitsOfNone) {
  Rig& r = rig();
  for (const RestStart start : {RestStart::kApproach, RestStart::kKinematicApproach}) {
    PuttScratch scratch;
    const FullPuttResult none = r.putt(0.05, 1.4, r.handoff(start), &scratch);
    // The owned set of identity values, and each identity wrapper built by hand.
    PlantWrappers identity(r.model, PlantEffectValues{}, 5);
    const FullPuttResult owned = r.putt(0.05, 1.4, r.handoff(start), &scratch, identity.effects());
    TorqueNoiseArm still(r.model.arm(), 0.0, 9);
    const ClubSpeedScale one(1.0);
    const LaunchAngleBias straight(0.0);
    perception::DelayedPerception now(0.0);
    perception::OffsetPerception here({0.0, 0.0});
    const PlantEffects by_hand{&still, &one, &straight, {&now, &here}};
    EXPECT_TRUE(by_hand.ideal_arm());
    EXPECT_TRUE(by_hand.ideal_perception());
    const FullPuttResult hand = r.putt(0.05, 1.4, r.handoff(start), &scratch, by_hand);
    const bool cached = start == RestStart::kApproach;
    expect_same_bits(none, owned, "PlantWrappers of identity values", !cached);
    expect_same_bits(none, hand, "identity wrappers", !cached);
    // Ideal wrappers keep the approach cache: the later putts' approach was not simulated.
    if (cached) EXPECT_LT(hand.arm_steps, none.arm_steps);
  }
}

TEST(TorqueNoiseArm, AddsTheSeededDrawsToTheAppliedForcesAtEveryWrite) {
  Rig& r = rig();
  sim::DataPtr d = r.world.make_data();
  const SimIds ids = find_sim_ids(r.world);
  MujocoArm simulated(ids.arm, d.get());
  TorqueNoiseArm noisy(r.model.arm(), 0.01, 42);
  EXPECT_FALSE(noisy.ideal());
  noisy.wrap(simulated);
  ModuleCommand command;
  for (int j = 0; j < 7; ++j) command.tau[j] = 0.1 * (j + 1);
  Rng rng(42);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto expect_draws = [&] {
    for (int j = 0; j < 7; ++j) {
      const double tau = 0.01 * r.model.arm().torque_limit()[j] * normal(rng);
      EXPECT_NEAR(d->qfrc_applied[ids.arm.dof[static_cast<std::size_t>(j)]], tau, 1e-15) << j;
      EXPECT_EQ(d->ctrl[ids.arm.actuator[static_cast<std::size_t>(j)]], command.tau[j]) << j;
    }
  };
  const long before = mg::testing::allocations();
  noisy.write(command);
  const long allocated = mg::testing::allocations() - before;
  EXPECT_EQ(allocated, 0) << "a write is real-time safe";
  expect_draws();
  noisy.write(command);  // a fresh draw replaces the last one
  expect_draws();
  // The measurement passes through.
  d->qpos[ids.arm.qpos[2]] = 0.3;
  EXPECT_EQ(noisy.read().q[2], simulated.read().q[2]);
  // Wrapped again, it starts afresh: the first draws again.
  for (int j = 0; j < 7; ++j) d->qfrc_applied[ids.arm.dof[static_cast<std::size_t>(j)]] = 0.0;
  noisy.wrap(simulated);
  rng.seed(42);
  normal.reset();
  noisy.write(command);
  expect_draws();
  EXPECT_TRUE(TorqueNoiseArm(r.model.arm(), 0.0, 1).ideal());
}

TEST(ClubSpeedScale, TheArmReachesAFractionWithinTheEnvelope) {
  const ControllerConfig config;
  const HitRequest asked{0.1, 1.6};
  const HitRequest same_hit = ClubSpeedScale(1.0).reach(asked, config);
  EXPECT_EQ(same_hit.angle, asked.angle);
  EXPECT_EQ(same_hit.speed, asked.speed);
  const HitRequest slow = ClubSpeedScale(0.97).reach(asked, config);
  EXPECT_EQ(slow.angle, asked.angle);
  EXPECT_EQ(slow.speed, 1.6 * 0.97);
  EXPECT_EQ(ClubSpeedScale(5.0).reach(asked, config).speed, config.speed_max);
  EXPECT_EQ(ClubSpeedScale(0.1).reach({0.0, config.speed_min}, config).speed, config.speed_min);
  EXPECT_TRUE(ClubSpeedScale(1.0).ideal());
  EXPECT_FALSE(ClubSpeedScale(0.97).ideal());
}

TEST(LaunchAngleBias, TurnsTheBallsVelocityAndSpinAboutTheVertical) {
  const sim::World& w = rig().ball_world;
  sim::DataPtr d = w.make_data();
  w.reset(d.get());
  w.place_ball(d.get(), {0.0, 0.0});
  mjtNum* v = d->qvel + w.ids().ball_dof;
  v[0] = 2.0;
  v[1] = 0.0;
  v[2] = 0.1;
  LaunchAngleBias(0.0).after_release(w, d.get());
  EXPECT_EQ(v[0], 2.0);
  EXPECT_EQ(v[1], 0.0);
  const mjtNum* q = d->qpos + w.ids().ball_qpos + 3;
  const double w0 = q[0];
  LaunchAngleBias(0.1).after_release(w, d.get());
  EXPECT_NEAR(std::atan2(v[1], v[0]), 0.1, 1e-12);
  EXPECT_NEAR(std::hypot(v[0], v[1]), 2.0, 1e-12);
  EXPECT_EQ(v[2], 0.1);
  EXPECT_NEAR(2.0 * std::atan2(q[3], q[0]), 0.1, 1e-12) << "orientation turned from " << w0;
  EXPECT_TRUE(LaunchAngleBias(0.0).ideal());
}

TEST(PlantEffects, BadValuesAreOneLineInputErrors) {
  const ModuleModel& model = rig().model;
  EXPECT_THROW(TorqueNoiseArm(model.arm(), -0.1, 1), InputError);
  EXPECT_THROW(ClubSpeedScale(std::nan("")), InputError);
  EXPECT_THROW(LaunchAngleBias(1.0), InputError);
  PlantEffectValues v;
  v.perception_latency = 2.0;
  try {
    PlantWrappers w(model, v, 0);
    ADD_FAILURE() << "accepted a latency of 2 s";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("perception_latency"), std::string::npos) << e.what();
  }
}

// Each effect acts in a putt as documented.
TEST(PlantEffects, EachEffectActsInAPutt) {
  Rig& r = rig();
  const FullPuttOptions o = r.handoff(RestStart::kKinematicApproach);
  const FullPuttResult none = r.putt(0.0, 1.4, o);
  ASSERT_TRUE(none.hit);
  const auto with = [&](const PlantEffectValues& v) {
    PlantWrappers w(r.model, v, 3);
    return r.putt(0.0, 1.4, o, nullptr, w.effects());
  };
  PlantEffectValues slow;
  slow.club_speed_scale = 0.9;
  EXPECT_NEAR(with(slow).club.speed / none.club.speed, 0.9, 0.02);
  PlantEffectValues biased;
  biased.launch_angle_bias = 0.02;
  const FullPuttResult turned = with(biased);
  EXPECT_TRUE(same(turned.club.speed, none.club.speed)) << "the club is as without";
  EXPECT_NEAR(turned.launch.angle - none.launch.angle, 0.02, 2e-3);
  // The module hits only a ball it perceives within ball_tolerance (3 cm) of its hitting point.
  PlantEffectValues off;
  off.perceived_ball_offset = {0.0, 0.02};
  EXPECT_TRUE(with(off).hit);
  off.perceived_ball_offset = {0.0, 0.05};
  const FullPuttResult aside = with(off);
  EXPECT_FALSE(aside.hit);
  EXPECT_TRUE(aside.hit_refused);
  // (The latency of a ball at rest changes what the module perceives only in its age:
  // DelayedPerception's own test has the delay.)
  PlantEffectValues late;
  late.perception_latency = 0.05;
  EXPECT_TRUE(with(late).hit);
}

// A plant's arm is never taken kinematically nor from the cache: with torque noise the kinematic
// start is the simulated approach, bit for bit, and a used scratch and a reused wrapper give the
// bits of fresh ones.
TEST(PlantEffects, ANoisyArmIsSimulatedAndNeverCached) {
  Rig& r = rig();
  PlantEffectValues v;
  v.torque_noise = 0.002;
  PlantWrappers reused(r.model, v, 11);
  ASSERT_FALSE(reused.effects().ideal_arm());
  PuttScratch scratch;
  const FullPuttResult first =
      r.putt(0.05, 1.4, r.handoff(RestStart::kApproach), &scratch, reused.effects());
  ASSERT_TRUE(first.hit);
  const FullPuttResult again =
      r.putt(0.05, 1.4, r.handoff(RestStart::kApproach), &scratch, reused.effects());
  expect_same_bits(first, again, "used scratch, reused wrappers");
  PlantWrappers fresh(r.model, v, 11);
  const FullPuttResult kinematic =
      r.putt(0.05, 1.4, r.handoff(RestStart::kKinematicApproach), nullptr, fresh.effects());
  expect_same_bits(first, kinematic, "kinematic start with a noisy arm");
  PlantWrappers other(r.model, v, 12);
  const FullPuttResult other_seed =
      r.putt(0.05, 1.4, r.handoff(RestStart::kApproach), &scratch, other.effects());
  EXPECT_FALSE(same(other_seed.launch.angle, first.launch.angle)) << "another seed, other draws";
}

}  // namespace
}  // namespace mg::control
