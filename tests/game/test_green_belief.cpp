// The robot's belief of the green in a round (game::GreenBelief): revised from paths it watches.
#include "game/green_belief.hpp"

#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "field/field.hpp"
#include "plant/plant.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"

namespace mg::game {
namespace {

// Ball-only paths on the true lane (the field file with `truth`), 10 ms apart, in five directions.
std::vector<std::vector<sim::BallSample>> paths_on(const field::Field& survey,
                                                   const plant::Plant& truth) {
  const sim::World world(plant::true_field(survey, truth));
  auto d = world.make_data();
  std::vector<std::vector<sim::BallSample>> out;
  for (double angle : {0.0, 0.12, -0.12, 0.25, -0.25}) {
    sim::PuttRequest q;
    q.angle = angle;
    q.speed = 1.6;
    q.record_interval = 0.01;
    out.push_back(sim::simulate_putt(world, d.get(), {-0.2, 0.5}, q).trajectory);
  }
  return out;
}

TEST(GreenBelief, LearnsASlowerTiltedGreenFromThePathsItWatches) {
  const field::Field survey = field::load_field("flat");
  plant::Plant truth;
  truth.field.rolling_resistance_scale = 1.15;
  truth.field.extra_slope = {0.002, -0.0015};
  GreenBelief belief({}, survey, 0.0005);
  EXPECT_FALSE(belief.plant().field.rolling_resistance_scale.has_value());  // the survey at first
  Rng rng(4);
  for (const auto& path : paths_on(survey, truth))
    EXPECT_TRUE(belief.watch(survey, survey.hole.position, path, rng));
  EXPECT_EQ(belief.paths(), 5);
  const auto& b = belief.plant().field;
  ASSERT_TRUE(b.rolling_resistance_scale.has_value());
  EXPECT_NEAR(*b.rolling_resistance_scale, 1.15, 0.02);
  EXPECT_NEAR(b.extra_slope[0], 0.002, 0.001);
  EXPECT_NEAR(b.extra_slope[1], -0.0015, 0.001);
  EXPECT_LT(belief.std()[0], 0.02);

  // The same paths and the same vision seed: the same bits.
  GreenBelief again({}, survey, 0.0005);
  Rng rng2(4);
  for (const auto& path : paths_on(survey, truth))
    again.watch(survey, survey.hole.position, path, rng2);
  EXPECT_EQ(*again.plant().field.rolling_resistance_scale, *b.rolling_resistance_scale);
  EXPECT_EQ(again.plant().field.extra_slope, b.extra_slope);

  // A path with nothing on the open lane to fit changes nothing.
  EXPECT_FALSE(belief.watch(survey, survey.hole.position, {}, rng));
}

}  // namespace
}  // namespace mg::game
