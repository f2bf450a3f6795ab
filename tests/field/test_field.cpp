#include "field/field.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg::field {
namespace {

const char* kMinimal = R"(
format_version: 1
name: test
lane: {bounds: [-0.3, 2.7, -0.6, 0.6]}
tee: [0.0, 0.0]
hole: {position: [2.0, 0.0]}
rolling_resistance: 0.131
surface:
  - {type: plane}
)";

Field parse(const std::string& text) { return parse_field(text, "test.yaml", "."); }

// Replaces the first occurrence of `from` in the minimal field.
std::string edited(const std::string& from, const std::string& to) {
  std::string s = kMinimal;
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return s.replace(pos, from.size(), to);
}

void expect_error_mentions(const std::string& text, const std::string& needle) {
  try {
    parse(text);
    ADD_FAILURE() << "expected an InputError mentioning '" << needle << "'";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
  }
}

TEST(Field, MinimalFileGetsDocumentedDefaults) {
  const Field f = parse(kMinimal);
  EXPECT_EQ(f.name, "test");
  EXPECT_DOUBLE_EQ(f.hole.diameter, 0.108);
  EXPECT_NEAR(f.ball.radius, 0.0427 / 2, 1e-4);
  EXPECT_DOUBLE_EQ(f.rolling_resistance, 0.131);
}

TEST(Field, BadInputNamesTheProblem) {
  expect_error_mentions("", "empty");
  expect_error_mentions("lane: [", "malformed YAML");
  expect_error_mentions(edited("rolling_resistance: 0.131", ""), "rolling_resistance");
  expect_error_mentions(edited("rolling_resistance: 0.131", "rolling_resistance: .nan"),
                        "rolling_resistance");
  expect_error_mentions(edited("rolling_resistance: 0.131", "rolling_resistance: abc"),
                        "rolling_resistance");
  expect_error_mentions(edited("rolling_resistance: 0.131", "rolling_resistance: 3"),
                        "rolling_resistance");
  expect_error_mentions(
      edited("rolling_resistance: 0.131", "rolling_resistance: 0.1\nrolling_resistence: 0.1"),
      "rolling_resistence");
  expect_error_mentions(edited("position: [2.0, 0.0]", "position: [3.5, 0.0]"), "hole");
  expect_error_mentions(edited("position: [2.0, 0.0]", "position: [2.0, 0.58]"), "hole");
  expect_error_mentions(edited("tee: [0.0, 0.0]", "tee: [0.0]"), "tee");
  expect_error_mentions(edited("format_version: 1", "format_version: 7"), "format_version");
  expect_error_mentions(edited("{type: plane}", "{type: volcano}"), "volcano");
  expect_error_mentions(
      edited("{type: plane}", "{type: bump, center: [1, 0], height: 0.1, sigma: [0, 1]}"), "sigma");
  expect_error_mentions(edited("{type: plane}", "{type: plane, slope_x: 3}"), "steeper");
  expect_error_mentions(edited("{type: plane}", "{type: heightmap, file: missing.png}"),
                        "missing.png");
  expect_error_mentions(edited("surface:\n  - {type: plane}", "surface: []"), "surface");
}

// yaml-cpp read the first of two equal keys and ignored a second
// document; a name with a control character split one-line reports. All are refused.
TEST(Field, DuplicateKeysSecondDocumentsAndControlCharactersInTheNameAreRefused) {
  expect_error_mentions(
      edited("rolling_resistance: 0.131", "rolling_resistance: 0.131\nrolling_resistance: 0.5"),
      "test.yaml: rolling_resistance: duplicate key");
  expect_error_mentions(edited("position: [2.0, 0.0]}", "position: [2.0, 0.0], position: [1, 0]}"),
                        "test.yaml: hole.position: duplicate key");
  expect_error_mentions(edited("- {type: plane}", "- {type: plane, type: bump}"),
                        "test.yaml: surface[0].type: duplicate key");
  expect_error_mentions(std::string(kMinimal) + "---\nname: second\n",
                        "test.yaml: a second YAML document at line");
  expect_error_mentions(edited("name: test", "name: \"te\\nst\""),
                        "test.yaml: name: expected a name without control characters");
  expect_error_mentions(edited("name: test", "name: \"te\\x1bst\""), "0x1b");
  EXPECT_EQ(parse(std::string("---\n") + kMinimal).name, "test");  // one marked document is fine
}

TEST(Field, FlattenTermDefaultsToTheTeeAndChecksItsRadii) {
  const Field f =
      parse(edited("{type: plane}", "{type: plane, slope_x: 0.04}\n  - {type: flatten}"));
  ASSERT_EQ(f.surface.terms.size(), 2u);
  const auto& pad = std::get<FlattenTerm>(f.surface.terms[1]);
  EXPECT_EQ(pad.center, f.tee);
  EXPECT_EQ(f.surface.gradient(f.tee[0], f.tee[1])[0], 0.0);
  EXPECT_NEAR(f.surface.gradient(0.5, 0.0)[0], 0.04, 1e-15);
  expect_error_mentions(edited("{type: plane}", "{type: plane}\n  - {type: flatten, radius: -1}"),
                        "surface[1].radius");
  expect_error_mentions(
      edited("{type: plane}",
             "{type: plane}\n  - {type: flatten, radius: 0.1, blend_radius: 0.05}"),
      "surface[1].blend_radius");
  expect_error_mentions(edited("{type: plane}", "{type: plane}\n  - {type: flatten, size: 1}"),
                        "surface[1].size");
}

TEST(Field, UnknownShippedNameListsTheShippedOnes) {
  try {
    load_field("no-such-field");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("flat"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_field("/nonexistent/field.yaml"), IoError);
}

TEST(Field, ShippedFieldsLoadAndFitBesideTheArm) {
  const auto names = list_shipped_fields();
  for (const char* expected : {"flat", "multiple-hills", "regular-hill", "arctan"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  for (const auto& name : names) {
    const Field f = load_field(name);
    EXPECT_EQ(f.name, name);
    EXPECT_FALSE(f.description.empty());
    // The WAM stands beside the tee and reaches about 1 m: the tee is near the lane's start.
    EXPECT_LT(f.tee[0] - f.bounds[0], 1.0) << name;
    EXPECT_GT(std::hypot(f.hole.position[0] - f.tee[0], f.hole.position[1] - f.tee[1]), 1.0);
  }
}

TEST(Field, FlatFieldIsLevel) {
  const Field f = load_field("flat");
  for (double x = f.bounds[0]; x <= f.bounds[1]; x += 0.1)
    EXPECT_EQ(f.height(x, 0.3), f.height(f.tee[0], f.tee[1]));
}

TEST(Field, MultipleHillsIsAnUpwardSlopeWithTwoBumps) {
  const Field f = load_field("multiple-hills");
  EXPECT_GT(f.height(f.hole.position[0], f.hole.position[1]), f.height(f.tee[0], f.tee[1]) + 0.05);
  // Two local maxima above the underlying slope along lines through the bumps.
  int bumps = 0;
  for (const auto& term : f.surface.terms) bumps += std::holds_alternative<BumpTerm>(term);
  EXPECT_EQ(bumps, 2);
}

TEST(Field, RegularHillCrestIsRightBeforeTheHole) {
  const Field f = load_field("regular-hill");
  const double hx = f.hole.position[0], hy = f.hole.position[1];
  double crest_x = f.tee[0], crest_z = -1e9;
  for (double x = f.tee[0]; x <= hx; x += 0.005)
    if (f.height(x, hy) > crest_z) crest_z = f.height(x, hy), crest_x = x;
  EXPECT_GT(crest_x, f.tee[0] + 0.5 * (hx - f.tee[0]));  // the crest is in the hole's half
  EXPECT_LT(hx - crest_x, 0.4);                          // and right before the hole
  EXPECT_LT(f.surface.gradient(hx, hy)[0], -0.05);       // the ball arrives going downhill
}

TEST(Field, ArctanVariesAlongBothAxes) {
  const Field f = load_field("arctan");
  const auto g1 = f.surface.gradient(1.6, 0.3), g2 = f.surface.gradient(0.6, -0.3);
  EXPECT_GT(std::abs(g1[0]), 0.01);
  EXPECT_GT(std::abs(g1[1]), 0.01);
  EXPECT_LT(g1[1] * g2[1], 0.0);  // the cross slope changes sign across the lane: a saddle
  EXPECT_LT(f.hole.depth, load_field("flat").hole.depth);  // the shallow hole
}

}  // namespace
}  // namespace mg::field
