// Belief files: the plant's format plus std and putts; round trip, JSON, bad files in one line.
#include "belief/belief.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "field/field.hpp"

namespace mg::belief {
namespace {

namespace fs = std::filesystem;

constexpr const char* kBelief = R"(format_version: 1
field:
  rolling_resistance: 0.1467
  extra_slope: [0.002, -0.0015]
  hole_offset: [0.001, 0.0]
arm:
  launch_angle_bias: -0.003
  club_speed_scale: 0.97
std:
  field:
    rolling_resistance: 0.0012
    extra_slope: [0.0001, 0.00012]
  arm:
    launch_angle_bias: 0.0004
    club_speed_scale: 0.002
putts: 5
)";

// Errors of a belief file: `yaml` after its version line (a list or broken YAML as it stands).
std::string error_of(const std::string& yaml) {
  const bool versioned =
      yaml.rfind("- ", 0) != 0 && yaml.find("{extra_slope: [0, 0.001]\n") == std::string::npos;
  try {
    parse_belief(versioned ? "format_version: 1\n" + yaml : yaml, "b.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A fresh folder under the test's temporary directory.
fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("mg_belief_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Belief, ReadsThePlantKeysTheStdAndThePutts) {
  const Belief b = parse_belief(kBelief, "b.yaml");
  EXPECT_DOUBLE_EQ(*b.estimate.field.rolling_resistance, 0.1467);
  EXPECT_DOUBLE_EQ(b.estimate.field.extra_slope[1], -0.0015);
  EXPECT_DOUBLE_EQ(b.estimate.arm.club_speed_scale, 0.97);
  EXPECT_DOUBLE_EQ(*b.std.field.rolling_resistance, 0.0012);
  EXPECT_DOUBLE_EQ(b.std.field.extra_slope[1], 0.00012);
  EXPECT_DOUBLE_EQ(b.std.arm.launch_angle_bias, 0.0004);
  EXPECT_DOUBLE_EQ(b.std.arm.club_speed_scale, 0.002);
  EXPECT_EQ(b.std.arm.club_restitution_scale, 0.0);  // not estimated
  EXPECT_EQ(b.putts, 5);
  EXPECT_EQ(b.estimate.hash.size(), 16u);
}

TEST(Belief, APlantFileIsABeliefWithoutUncertainty) {
  const Belief b = parse_belief("format_version: 1\narm: {launch_angle_bias: 0.001}\n", "p.yaml");
  EXPECT_DOUBLE_EQ(b.estimate.arm.launch_angle_bias, 0.001);
  EXPECT_EQ(b.putts, 0);
  EXPECT_EQ(b.std.arm.launch_angle_bias, 0.0);
  EXPECT_THROW(parse_belief("", "e.yaml"), InputError);  // a version is required, as for plants
}

TEST(Belief, RoundTripsThroughItsText) {
  const Belief b = parse_belief(kBelief, "b.yaml");
  const Belief c = parse_belief(belief_to_yaml(b), "c.yaml");
  EXPECT_EQ(*c.estimate.field.rolling_resistance, *b.estimate.field.rolling_resistance);
  EXPECT_EQ(c.estimate.field.extra_slope, b.estimate.field.extra_slope);
  EXPECT_EQ(c.estimate.field.hole_offset, b.estimate.field.hole_offset);
  EXPECT_EQ(c.estimate.arm.launch_angle_bias, b.estimate.arm.launch_angle_bias);
  EXPECT_EQ(c.estimate.arm.club_speed_scale, b.estimate.arm.club_speed_scale);
  EXPECT_EQ(*c.std.field.rolling_resistance, *b.std.field.rolling_resistance);
  EXPECT_EQ(c.std.field.extra_slope, b.std.field.extra_slope);
  EXPECT_EQ(c.std.arm.launch_angle_bias, b.std.arm.launch_angle_bias);
  EXPECT_EQ(c.std.arm.club_speed_scale, b.std.arm.club_speed_scale);
  EXPECT_EQ(c.putts, 5);
}

TEST(Belief, JsonGivesAbsoluteResistanceAndEveryKey) {
  const field::Field f = field::load_field("flat");
  Belief b = parse_belief(
      "format_version: 1\nfield: {rolling_resistance_scale: 1.1}\nstd: {field: "
      "{rolling_resistance_scale: 0.01}}\nputts: 3\n",
      "b.yaml");
  const auto j = belief_to_json(b, f);
  EXPECT_DOUBLE_EQ(j["field"]["rolling_resistance"].get<double>(), 1.1 * f.rolling_resistance);
  EXPECT_DOUBLE_EQ(j["std"]["field"]["rolling_resistance"].get<double>(),
                   0.01 * f.rolling_resistance);
  EXPECT_DOUBLE_EQ(j["field"]["sliding_friction"].get<double>(), f.sliding_friction);
  EXPECT_EQ(j["field"]["extra_slope"].size(), 2u);
  EXPECT_EQ(j["field"]["hole_offset"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["arm"]["club_speed_scale"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["arm"]["launch_angle_bias"].get<double>(), 0.0);
  EXPECT_EQ(j["std"]["arm"].size(), 2u);
  EXPECT_EQ(j["putts"].get<int>(), 3);
}

TEST(Belief, TheBelievedFieldIsTheSurveyWithTheEstimate) {
  const field::Field f = field::load_field("flat");
  const Belief b = parse_belief(kBelief, "b.yaml");
  const field::Field g = believed_field(f, b);
  EXPECT_DOUBLE_EQ(g.rolling_resistance, 0.1467);
  const auto grad = g.surface.gradient(1.0, 0.2);
  EXPECT_NEAR(grad[0], 0.002, 1e-15);
  EXPECT_NEAR(grad[1], -0.0015, 1e-15);
}

// A belief may hold a shape beyond the keys (a spatial correction): its lane has it, its JSON
// shows it.
TEST(Belief, BumpsInABeliefShapeItsLane) {
  const field::Field f = field::load_field("flat");
  const Belief b = parse_belief(
      "format_version: 1\nfield: {bumps: [{center: [1, 0], height: 0.002, sigma: [0.2, 0.2]}]}\n",
      "b.yaml");
  EXPECT_NEAR(believed_field(f, b).height(1.0, 0.0) - f.height(1.0, 0.0), 0.002, 1e-12);
  const auto j = belief_to_json(b, f);
  ASSERT_EQ(j["field"]["bumps"].size(), 1u);
  EXPECT_DOUBLE_EQ(j["field"]["bumps"][0]["height"].get<double>(), 0.002);
  EXPECT_EQ(parse_belief(belief_to_yaml(b), "c.yaml").estimate.field.bumps.size(), 1u);
}

// Every bad file is one line naming the file and the key.
TEST(Belief, BadFilesNameTheFileAndTheKey) {
  const auto one_line = [](const std::string& e) { return e.find('\n') == std::string::npos; };
  const std::vector<std::pair<std::string, std::string>> cases{
      {"putts: 3\nstd: {field: {grass: 1}}\n", "b.yaml: std.field.grass: unknown key"},
      {"colour: blue\n", "b.yaml: colour: unknown key"},
      {"std: {arm: {launch_angle_bias: .nan}}\n", "std.arm.launch_angle_bias"},
      {"arm: {launch_angle_bias: nan}\n", "arm.launch_angle_bias"},
      {"std: {arm: {club_speed_scale: -0.1}}\n", "std.arm.club_speed_scale"},
      {"std: {field: {extra_slope: [0.001, 7]}}\n", "std.field.extra_slope[1]"},
      {"arm: {club_speed_scale: 9}\n", "arm.club_speed_scale"},
      {"putts: 2.5\n", "b.yaml: putts"},
      {"putts: -1\n", "b.yaml: putts"},
      {"field: {extra_slope: [0, 0.001]}\nfield: {extra_slope: [0, 0]}\n",
       "b.yaml: field: duplicate key"},
      {"std: {arm: {club_speed_scale: 0.1, club_speed_scale: 0.2}}\n",
       "b.yaml: std.arm.club_speed_scale: duplicate key"},
      {"putts: [1, 2]\n", "b.yaml: putts"},
      {"- 1\n- 2\n", "b.yaml"},
      {"field: {extra_slope: [0, 0.001]\n", "b.yaml: malformed YAML"},
      {"std: {field: {bumps: [{center: [1, 0], height: 0.001, sigma: [0.2, 0.2]}]}}\n",
       "b.yaml: std.field.bumps: bumps have no standard deviation"},
  };
  for (const auto& [yaml, expected] : cases) {
    const std::string e = error_of(yaml);
    EXPECT_NE(e.find(expected), std::string::npos) << yaml << " -> " << e;
    EXPECT_TRUE(one_line(e)) << e;
  }
}

TEST(Belief, ADirectoryOrAFifoIsRefusedInOneLine) {
  const fs::path dir = scratch("special");
  const fs::path fifo = dir / "belief.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const fs::path& p : {dir, fifo, dir / "missing.yaml"}) {
    try {
      load_belief(p);
      ADD_FAILURE() << p << " was read";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(p.filename().string()), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  std::ofstream(dir / "good.yaml") << kBelief;
  EXPECT_EQ(load_belief(dir / "good.yaml").putts, 5);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mg::belief
