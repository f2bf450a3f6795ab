// The `situations` section of field files: shapes, defaults, sampling, command-line specs, errors.
#include "field/situations.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "field/field.hpp"

namespace mg::field {
namespace {

std::string with_situations(const std::string& section) {
  return std::string(R"(
format_version: 1
name: test
lane: {bounds: [-0.3, 2.7, -0.6, 0.6]}
tee: [0.0, 0.0]
hole: {position: [2.0, 0.0]}
rolling_resistance: 0.131
surface:
  - {type: plane}
)") + section;
}

Field parse(const std::string& text) { return parse_field(text, "test.yaml", "."); }

void expect_error(const std::string& section, const std::string& needle) {
  try {
    parse(with_situations(section));
    ADD_FAILURE() << "expected an error mentioning '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.yaml"), std::string::npos) << e.what();
  }
}

TEST(Situations, LineGivesEquallySpacedHolesEndsIncluded) {
  const Field f =
      parse(with_situations("situations: {line: {from: [2.0, -0.2], to: [2.0, 0.4], count: 11}, "
                            "outputs: [angle], speed: 1.5}\n"));
  const Situations& s = f.situations;
  EXPECT_TRUE(s.from_file);
  EXPECT_FALSE(s.learn_speed);
  EXPECT_DOUBLE_EQ(s.speed, 1.5);
  const auto p = s.collection_points();
  ASSERT_EQ(p.size(), 11u);
  EXPECT_DOUBLE_EQ(p.front()[1], -0.2);
  EXPECT_DOUBLE_EQ(p.back()[1], 0.4);
  for (std::size_t i = 1; i < p.size(); ++i) EXPECT_NEAR(p[i][1] - p[i - 1][1], 0.06, 1e-12);
}

TEST(Situations, GridIsXMajorAndSamplesStayInTheRectangle) {
  const Field f = parse(
      with_situations("situations: {grid: {x: [1.8, 2.4], y: [0.0, 0.3], counts: [7, 4]}}\n"));
  const auto p = f.situations.collection_points();
  ASSERT_EQ(p.size(), 28u);
  EXPECT_DOUBLE_EQ(p[1][0], 1.8);
  EXPECT_DOUBLE_EQ(p[1][1], 0.1);
  EXPECT_DOUBLE_EQ(p[4][0], 1.9);
  const auto a = f.situations.sample(200, 5), b = f.situations.sample(200, 5),
             c = f.situations.sample(30, 5);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i], b[i]);  // seeded
    EXPECT_GE(a[i][0], 1.8);
    EXPECT_LE(a[i][0], 2.4);
    EXPECT_GE(a[i][1], 0.0);
    EXPECT_LE(a[i][1], 0.3);
  }
  for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(a[i], c[i]);  // the first 30 of 200
}

TEST(Situations, ListAndDefault) {
  const Field f = parse(with_situations(
      "situations: {list: {points: [[1.5, 0.1], [2.0, -0.1]]}, strategy: min-angle}\n"));
  EXPECT_EQ(f.situations.collection_points().size(), 2u);
  EXPECT_EQ(f.situations.strategy, "min-angle");
  const auto s = f.situations.sample(10, 1);
  for (const auto& h : s)
    EXPECT_TRUE(h == (std::array<double, 2>{1.5, 0.1}) || h == (std::array<double, 2>{2.0, -0.1}));
  const Field d = parse(with_situations(""));
  EXPECT_FALSE(d.situations.from_file);
  EXPECT_EQ(d.situations.collection_points().size(), 9u);
  EXPECT_TRUE(d.situations.learn_speed);
}

TEST(Situations, FileErrorsNameTheKey) {
  expect_error("situations: {outputs: [angle, speed]}\n", "exactly one of line, grid, box, list");
  expect_error(
      "situations: {line: {from: [2, 0], to: [2, 0.3], count: 3}, grid: {x: [1, 2], y: [0, 1], "
      "counts: [2, 2]}}\n",
      "exactly one");
  expect_error("situations: {line: {from: [2, 0], to: [2, 0.3], count: 0}}\n", "count");
  expect_error("situations: {line: {from: [2, 0], to: [2, 0.3], count: 2.5}}\n", "whole number");
  expect_error("situations: {line: {from: [2, 0], to: [2, 0.9], count: 3}}\n", "outside the lane");
  expect_error("situations: {line: {from: [2, 0], to: [2, 0.3], count: 3}, outputs: [angle]}\n",
               "speed");
  expect_error("situations: {line: {from: [2, 0], to: [2, 0.3], count: 3}, speed: 1.5}\n",
               "only for outputs: [angle]");
  expect_error("situations: {line: {from: [2, 0], to: [2, 0.3], count: 3}, strategy: fastest}\n",
               "min-speed or min-angle");
  expect_error("situations: {line: {from: [2, 0], to: [2, 0.3], count: 3}, colour: red}\n",
               "unknown key");
  expect_error("situations: {grid: {x: [2.4, 1.8], y: [0, 0.3], counts: [2, 2]}}\n", "[low, high]");
  expect_error("situations: {list: {points: [[0.0, 0.0]]}}\n", "on the tee");
  expect_error("situations: {list: {points: [[1.0, nan]]}}\n", "finite");
}

TEST(Situations, CommandLineSpecs) {
  const Field f = parse(with_situations(""));
  const Situations line = parse_situations_spec("line:1.5,0:2.0,0.2:6", f.situations);
  EXPECT_EQ(line.shape, RegionShape::kLine);
  EXPECT_EQ(line.collection_points().size(), 6u);
  const Situations grid = parse_situations_spec("grid:1.8,2.0:0,0.2:3,2", f.situations);
  EXPECT_EQ(grid.collection_points().size(), 6u);
  const Situations list = parse_situations_spec("list:1.5,0.1;2.0,0", f.situations);
  EXPECT_EQ(list.collection_points().size(), 2u);
  for (const char* bad : {"", "circle:1,2", "line:1,2:3", "line:1,a:2,0:3", "grid:1,2:0,1:0,2",
                          "list:1,2;3", "line:1,0:2,0:1e9"})
    EXPECT_THROW(parse_situations_spec(bad, f.situations), InputError) << bad;
  Situations off = parse_situations_spec("line:2,0:2,3:3", f.situations);
  EXPECT_THROW(off.validate(f), InputError);
}

TEST(Situations, EveryShippedFieldHasItsThesisRegion) {
  for (const std::string name : {"flat", "multiple-hills", "regular-hill", "arctan"}) {
    const Field f = load_field(name);
    EXPECT_TRUE(f.situations.from_file) << name;
  }
  EXPECT_EQ(load_field("flat").situations.collection_points().size(), 11u);
  EXPECT_FALSE(load_field("multiple-hills").situations.learn_speed);
  EXPECT_EQ(load_field("regular-hill").situations.shape, RegionShape::kGrid);
  EXPECT_EQ(load_field("arctan").situations.collection_points().size(), 28u);
  EXPECT_EQ(load_field("arctan").situations.strategy, "min-speed");
}

TEST(Situations, BoundsHoldEverySampleAndEveryCollectionPoint) {
  for (const std::string spec : {"line:2.2,-0.3:1.8,0.4:5", "grid:1.5,2.5:-0.3,0.3:1,3",
                                 "box:1.9,2.1:0.1,0.2:1,1", "list:2.0,0.1;1.7,-0.2;2.3,0.0"}) {
    const Field f = parse(with_situations(""));
    const Situations r = region_from_spec(f, spec);
    const auto b = r.bounds();
    auto inside = [&](std::array<double, 2> p) {
      return b[0] - 1e-12 <= p[0] && p[0] <= b[1] + 1e-12 && b[2] - 1e-12 <= p[1] &&
             p[1] <= b[3] + 1e-12;
    };
    for (const auto& p : r.sample(200, 3)) EXPECT_TRUE(inside(p)) << spec;
    for (const auto& p : r.collection_points()) EXPECT_TRUE(inside(p)) << spec;
    // the bounds are tight: some sample comes within 10 % of the span of each side that spans
    const auto s = r.sample(400, 5);
    for (int axis = 0; axis < 2; ++axis) {
      const double lo = b[2 * axis], hi = b[2 * axis + 1];
      if (hi - lo < 1e-12) continue;
      double seen_lo = hi, seen_hi = lo;
      for (const auto& p : s)
        seen_lo = std::min(seen_lo, p[axis]), seen_hi = std::max(seen_hi, p[axis]);
      EXPECT_LT(seen_lo - lo, 0.1 * (hi - lo)) << spec;
      EXPECT_LT(hi - seen_hi, 0.1 * (hi - lo)) << spec;
    }
  }
  const Field f = parse(with_situations(""));
  EXPECT_EQ(region_from_spec(f, "").bounds(), f.situations.bounds());
  EXPECT_THROW(region_from_spec(f, "box:1.5,9:-0.3,0.3:3,3"), InputError);  // off the lane
}

// Situations are (ball, hole) pairs; `ball:` gives where the ball may lie.
TEST(Situations, ABallRegionPairsEveryBallWithEveryHole) {
  const Field f =
      parse(with_situations("situations:\n  line: {from: [2.0, -0.2], to: [2.0, 0.2], count: 3}\n"
                            "  ball: {grid: {x: [0.0, 0.4], y: [-0.2, 0.2], counts: [2, 3]}}\n"));
  const Situations& s = f.situations;
  ASSERT_TRUE(s.balls.has_value());
  // A plane without obstacles is translation-invariant: xi = hole - ball says it all.
  EXPECT_FALSE(s.ball_inputs);
  EXPECT_EQ(s.learner_inputs(), (std::vector<std::string>{"xi_x", "xi_y"}));
  const auto c = s.collection_situations(f);
  ASSERT_EQ(c.size(), 6u * 3u);
  EXPECT_EQ(c.front().ball, (std::array<double, 2>{0.0, -0.2}));  // ball-major
  EXPECT_EQ(c[1].ball, c.front().ball);
  EXPECT_EQ(c[1].hole, (std::array<double, 2>{2.0, 0.0}));
  EXPECT_DOUBLE_EQ(situation_input(f, "xi_x", c[1]), 2.0);
  EXPECT_DOUBLE_EQ(situation_input(f, "xi_y", c[1]), 0.2);
  EXPECT_DOUBLE_EQ(situation_input(f, "ball_y", c[1]), -0.2);
  // Samples: the holes are those of the region without balls (the same streams), the balls lie
  // in the ball region and differ from sample to sample.
  Situations tee_only = s;
  tee_only.balls.reset();
  const auto with = s.sample_situations(f, 50, 7), without = tee_only.sample_situations(f, 50, 7);
  const auto holes = s.sample(50, 7);
  double spread = 0.0;
  for (std::size_t i = 0; i < with.size(); ++i) {
    EXPECT_EQ(with[i].hole, holes[i]);
    EXPECT_EQ(without[i].hole, holes[i]);
    EXPECT_EQ(without[i].ball, f.tee);
    EXPECT_GE(with[i].ball[0], 0.0);
    EXPECT_LE(with[i].ball[0], 0.4);
    EXPECT_GE(with[i].ball[1], -0.2);
    EXPECT_LE(with[i].ball[1], 0.2);
    spread = std::max(spread, std::abs(with[i].ball[0] - with[0].ball[0]));
  }
  EXPECT_GT(spread, 0.1);
}

TEST(Situations, OnASlopedLaneTheLearnersAlsoTakeTheBall) {
  Field f =
      parse(with_situations("situations:\n  grid: {x: [1.8, 2.2], y: [-0.1, 0.1], counts: [2, 2]}\n"
                            "  ball: {list: {points: [[0.0, 0.0], [0.3, 0.2]]}}\n"));
  EXPECT_FALSE(f.situations.ball_inputs);
  // A ridge across the lane: the surface list goes on with a hill term.
  const std::string hill =
      "  - {type: hill, crest: [1.0, 0.0], direction: [1.0, 0.0], height: 0.05, half_width: 0.4}\n"
      "situations:\n  grid: {x: [1.8, 2.2], y: [-0.1, 0.1], counts: [2, 2]}\n"
      "  ball: {list: {points: [[0.0, 0.0], [0.3, 0.2]]}}\n";
  f = parse(with_situations(hill));
  EXPECT_FALSE(translation_invariant(f));
  EXPECT_TRUE(f.situations.ball_inputs);
  EXPECT_EQ(f.situations.learner_inputs(),
            (std::vector<std::string>{"xi_x", "xi_y", "ball_x", "ball_y"}));
  EXPECT_EQ(f.situations.collection_situations(f).size(), 8u);
}

// A ball lies only where it can rest: on a plane steeper than the rest slope every ball off the
// tee is refused, and sampling keeps drawing until a ball rests.
TEST(Situations, BallsLieOnlyWhereABallRests) {
  const auto tilted = [](double slope, bool balls) {
    return with_situations(
        "  - {type: plane, slope_x: 0.0, slope_y: " + std::to_string(slope) +
        "}\nsituations:\n  line: {from: [2.0, -0.1], to: [2.0, 0.1], count: 3}\n" +
        (balls ? "  ball: {box: {x: [0.0, 0.4], y: [-0.2, 0.2], counts: [2, 2]}}\n" : ""));
  };
  const double limit = kRestSlopeFraction * 0.131;
  const Field gentle = parse(tilted(0.9 * limit, true)), steep = parse(tilted(1.1 * limit, false));
  EXPECT_TRUE(ball_rests(gentle, {0.3, 0.1}));
  EXPECT_FALSE(ball_rests(steep, {0.3, 0.1}));
  EXPECT_TRUE(playable(steep, Situation{steep.tee, {2.0, 0.0}}));  // the tee is the field's own
  EXPECT_FALSE(playable(steep, Situation{{0.3, 0.1}, {2.0, 0.0}}));
  EXPECT_EQ(gentle.situations.collection_situations(gentle).size(), 12u);
  try {
    parse(tilted(1.1 * limit, true));
    ADD_FAILURE() << "a ball region on a slope no ball rests on was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rest"), std::string::npos) << e.what();
  }
  Situations on_steep = steep.situations;
  on_steep.balls = gentle.situations.balls;
  EXPECT_TRUE(on_steep.collection_situations(steep).empty());
  EXPECT_THROW(on_steep.sample_situations(steep, 1, 3), InputError);
  // arctan: the saddle's cross slope (|grad z| = 0.146 at (0.3, 0)) does not hold a ball; its
  // flanks do. Every sampled ball rests.
  const Field arctan = load_field("arctan");
  EXPECT_FALSE(ball_rests(arctan, {0.3, 0.0}));
  EXPECT_TRUE(ball_rests(arctan, {0.3, 0.2}));
  Situations region = arctan.situations;
  region.balls =
      region_from_spec(arctan, "box:1.8,2.3:0.05,0.35:2,2", "box:0,0.4:-0.2,0.2:2,2").balls;
  ASSERT_TRUE(region.balls.has_value());
  for (const auto& s : region.sample_situations(arctan, 60, 3)) {
    EXPECT_TRUE(ball_rests(arctan, s.ball)) << s.ball[0] << ", " << s.ball[1];
  }
}

TEST(Situations, BallRegionErrorsNameTheBall) {
  expect_error(
      "situations: {line: {from: [2, 0], to: [2, 0.3], count: 3}, ball: {line: {from: [0, 0], to: "
      "[0, 0.9], count: 3}}}\n",
      "ball");
  expect_error(
      "situations: {line: {from: [2, 0], to: [2, 0.3], count: 3}, ball: {grid: {x: [0.2, 0.1], y: "
      "[0, 0.1], counts: [2, 2]}}}\n",
      "[low, high]");
  expect_error("situations: {line: {from: [2, 0], to: [2, 0.3], count: 3}, ball: {}}\n",
               "exactly one of line, grid, box, list");
  expect_error(
      "situations: {list: {points: [[1.0, 0.0]]}, ball: {list: {points: [[1.0, 0.01]]}}}\n",
      "every hole covers every ball");
}

}  // namespace
}  // namespace mg::field
