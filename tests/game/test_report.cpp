// The comparison tables of rounds: the plant comparison's means and its differences to the
// oracle paired hole by hole, against hand-computed values.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "game/course.hpp"
#include "game/report.hpp"

namespace mg::game {
namespace {

RoundResult round_of(Player player, std::vector<int> strokes) {
  RoundResult r;
  r.player = player;
  for (int s : strokes) r.holes.push_back(HoleResult{"flat", 2, s, true, {}});
  return r;
}

TEST(PlantComparison, MeansAndPairedDifferencesAreHandComputed) {
  const Course course = load_course("thesis");
  PlantRounds p;
  p.plant = "stand-in";
  p.revising = CourseRounds{course, {Player::kRobot, Player::kOracle}, {}};
  p.revising.rounds = {{round_of(Player::kRobot, {1, 1, 2, 1})},
                       {round_of(Player::kOracle, {1, 1, 1, 1})}};
  p.kept = CourseRounds{course, {Player::kRobot}, {{round_of(Player::kRobot, {3, 2, 2, 1})}}};
  const std::string md = plant_comparison_markdown({p}, 1);
  // Revising: strokes 1.25, differences (0, 0, 1, 0): mean 0.25, std 0.5, 1.96 x 0.5 / 2 = 0.49.
  EXPECT_NE(md.find("| robot, revising its belief | 1.25 ± 0.49 | +0.25 ± 0.49 | 75 % |"),
            std::string::npos)
      << md;
  // Kept: 2.00; differences (2, 1, 1, 0): mean 1, std 0.816, 1.96 x 0.816 / 2 = 0.80.
  EXPECT_NE(md.find("| robot, `--no-revise` | 2.00 ± 0.80 | +1.00 ± 0.80 | 25 % |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| stand-in | 4 | 1.25 | 2.00 | 1.00 |"), std::string::npos) << md;
  // Players that played different holes cannot be paired.
  p.kept.rounds[0][0].holes.pop_back();
  EXPECT_THROW(plant_comparison_markdown({p}, 1), InputError);
}

}  // namespace
}  // namespace mg::game
