// Plant files: parsing, validation, the identity, random plants and the true field.
#include "plant/plant.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "field/field.hpp"

namespace mg::plant {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    parse_plant(yaml, "p.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Plant, OnlyTheVersionIsTheIdentity) {
  EXPECT_TRUE(parse_plant("format_version: 1\n", "p.yaml").empty());
  EXPECT_TRUE(parse_plant("format_version: 1\narm: {club_speed_scale: 1.0}\n", "p.yaml").empty());
  EXPECT_FALSE(
      parse_plant("format_version: 1\narm: {launch_angle_bias: 0.001}\n", "p.yaml").empty());
  EXPECT_FALSE(
      parse_plant("format_version: 1\nfield: {extra_slope: [0, 0.001]}\n", "p.yaml").empty());
  EXPECT_FALSE(parse_plant("format_version: 1\nperception: {latency: 0.01}\n", "p.yaml").empty());
}

// A 0-byte plant or one without format_version was the identity; like fields
// and courses a plant now names its version. Item 6: a key given twice, or a second YAML
// document, is refused (yaml-cpp read the first value and ignored the second document).
TEST(Plant, TheVersionIsRequiredAndKeysAreUnique) {
  // yaml-cpp's own multi-document reader never returned on ",": one line, at once.
  EXPECT_EQ(error_of(","), "p.yaml: malformed YAML: nothing readable at line 1, column 1");
  EXPECT_EQ(error_of(""),
            "p.yaml: empty plant file (expected format_version: 1 and the keys that differ from "
            "the robot's model)");
  EXPECT_NE(error_of("# nothing but a comment\n").find("empty plant file"), std::string::npos);
  EXPECT_EQ(error_of("arm: {club_speed_scale: 0.9}\n"),
            "p.yaml: format_version: missing (required)");
  EXPECT_EQ(error_of("format_version: 1\narm: {club_speed_scale: 0.9, club_speed_scale: 1.1}\n"),
            "p.yaml: arm.club_speed_scale: duplicate key (a key may appear once per mapping)");
  EXPECT_NE(error_of("format_version: 1\nformat_version: 1\n").find("format_version: duplicate"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n---\narm: {club_speed_scale: 0.5}\n")
                .find("p.yaml: a second YAML document at line 2"),
            std::string::npos);
}

TEST(Plant, ReadsEveryKey) {
  const Plant p = parse_plant(R"(format_version: 1
field:
  rolling_resistance: 0.16
  sliding_friction: 0.25
  extra_slope: [0.003, -0.002]
  hole_offset: [0.01, 0.0]
arm:
  launch_angle_bias: -0.002
  club_speed_scale: 0.97
  club_restitution_scale: 1.05
  joint_friction: [0.5, 0.5, 0.3, 0.3, 0.1, 0.1, 0.05]
  torque_noise: 0.002
perception:
  noise: 0.002
  latency: 0.03
)",
                              "p.yaml");
  EXPECT_DOUBLE_EQ(*p.field.rolling_resistance, 0.16);
  EXPECT_DOUBLE_EQ(*p.field.sliding_friction, 0.25);
  EXPECT_DOUBLE_EQ(p.field.extra_slope[1], -0.002);
  EXPECT_DOUBLE_EQ(p.field.hole_offset[0], 0.01);
  EXPECT_DOUBLE_EQ(p.arm.launch_angle_bias, -0.002);
  EXPECT_DOUBLE_EQ(p.arm.club_speed_scale, 0.97);
  EXPECT_DOUBLE_EQ(p.arm.club_restitution_scale, 1.05);
  EXPECT_DOUBLE_EQ(p.arm.joint_friction[6], 0.05);
  EXPECT_DOUBLE_EQ(p.arm.torque_noise, 0.002);
  EXPECT_DOUBLE_EQ(p.perception.noise, 0.002);
  EXPECT_DOUBLE_EQ(p.perception.latency, 0.03);
  EXPECT_EQ(p.hash.size(), 16u);
}

TEST(Plant, BadFilesNameTheFileAndTheKey) {
  EXPECT_NE(
      error_of("format_version: 1\nfield: {grass: 1}\n").find("p.yaml: field.grass: unknown key"),
      std::string::npos);
  EXPECT_NE(error_of("format_version: 1\narms: {}\n").find("arms: unknown key"), std::string::npos);
  EXPECT_NE(error_of("format_version: 2\n").find("format_version"), std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "arm: {club_speed_scale: 7}\n")
                .find("arm.club_speed_scale"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "arm: {club_speed_scale: nan}\n")
                .find("arm.club_speed_scale"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "arm: {joint_friction: [1, 2]}\n")
                .find("arm.joint_friction"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "arm: {joint_friction: [0,0,0,0,0,0,-1]}\n")
                .find("arm.joint_friction[6]"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "field: {rolling_resistance: 0.1, rolling_resistance_scale: 1.1}\n")
                .find("give one"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "perception: {latency: 1e300}\n")
                .find("perception.latency"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "field: [1, 2]\n")
                .find("field"),
            std::string::npos);
  EXPECT_NE(error_of("{{{").find("malformed YAML"), std::string::npos);
  EXPECT_THROW(load_plant("/no/such/plant.yaml"), InputError);
  EXPECT_THROW(load_plant("/tmp"), InputError);  // a directory
}

TEST(Plant, RandomPlantsAreDeterministicInRangeAndRoundTrip) {
  const Plant a = random_plant(3), b = random_plant(3), c = random_plant(4);
  EXPECT_EQ(plant_to_yaml(a), plant_to_yaml(b));
  EXPECT_NE(plant_to_yaml(a), plant_to_yaml(c));
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    const Plant p = random_plant(seed);
    EXPECT_GE(*p.field.rolling_resistance_scale, 0.8);
    EXPECT_LE(*p.field.rolling_resistance_scale, 1.2);
    EXPECT_LE(std::abs(p.field.extra_slope[0]), 0.005);
    EXPECT_LE(std::abs(p.arm.launch_angle_bias), 0.005);
    EXPECT_LE(std::abs(p.arm.club_speed_scale - 1.0), 0.05);
    const Plant back = parse_plant(plant_to_yaml(p), "round trip");
    EXPECT_EQ(plant_to_yaml(back), plant_to_yaml(p));  // 17 digits: the same doubles
    EXPECT_EQ(*back.field.rolling_resistance_scale, *p.field.rolling_resistance_scale);
    EXPECT_EQ(back.arm.joint_friction, p.arm.joint_friction);
  }
}

TEST(Plant, TheTrueFieldAddsTheTiltAndTheGrass) {
  const field::Field belief = field::load_field("regular-hill");
  EXPECT_EQ(true_field(belief, Plant{}).surface.terms.size(), belief.surface.terms.size());
  Plant p;
  p.field.extra_slope = {0.003, -0.002};
  p.field.rolling_resistance_scale = 1.15;
  const field::Field truth = true_field(belief, p);
  EXPECT_DOUBLE_EQ(truth.rolling_resistance, belief.rolling_resistance * 1.15);
  EXPECT_DOUBLE_EQ(truth.sliding_friction, belief.sliding_friction);
  for (const auto [x, y] : {std::array<double, 2>{0.0, 0.0}, {1.0, 0.3}, {2.2, -0.4}}) {
    EXPECT_NEAR(truth.height(x, y) - belief.height(x, y), 0.003 * x - 0.002 * y, 1e-12);
    const auto gb = belief.surface.gradient(x, y), gt = truth.surface.gradient(x, y);
    EXPECT_NEAR(gt[0] - gb[0], 0.003, 1e-12);
    EXPECT_NEAR(gt[1] - gb[1], -0.002, 1e-12);
  }
  p = Plant{};
  p.field.rolling_resistance = 0.2;
  EXPECT_DOUBLE_EQ(true_field(belief, p).rolling_resistance, 0.2);
}

// Bumps the survey missed: read, checked, written back, and added to the true lane's surface.
TEST(Plant, BumpsAreReadCheckedWrittenAndAddedToTheSurface) {
  const Plant p = parse_plant(
      "format_version: 1\n"
      "field:\n"
      "  bumps:\n"
      "    - {center: [1.2, 0.1], height: 0.002, sigma: [0.3, 0.2]}\n"
      "    - {center: [0.6, -0.3], height: -0.001, sigma: [0.2, 0.2]}\n",
      "p.yaml");
  ASSERT_EQ(p.field.bumps.size(), 2u);
  EXPECT_TRUE(p.field_changed());
  EXPECT_FALSE(p.empty());
  EXPECT_EQ(plant_to_yaml(parse_plant(plant_to_yaml(p), "back")), plant_to_yaml(p));
  const field::Field belief = field::load_field("flat");
  const field::Field truth = true_field(belief, p);
  EXPECT_NEAR(truth.height(1.2, 0.1) - belief.height(1.2, 0.1),
              0.002 + -0.001 * std::exp(-0.5 * (0.36 / 0.04 + 0.16 / 0.04)), 1e-12);
  EXPECT_NEAR(truth.height(2.5, 0.5) - belief.height(2.5, 0.5), 0.0, 1e-6);

  EXPECT_NE(error_of("format_version: 1\nfield: {bumps: 3}\n").find("field.bumps: expected a list"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "field: {bumps: [{center: [1, 0], height: 0.2, sigma: [0.3, 0.3]}]}\n")
                .find("field.bumps[0].height"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "field: {bumps: [{center: [1, 0], height: 0.001, sigma: [0.3, 0]}]}\n")
                .find("field.bumps[0].sigma[1]"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "field: {bumps: [{center: [1, nan], height: 0.001, sigma: [0.3, 0.3]}]}\n")
                .find("field.bumps[0].center[1]"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "field: {bumps: [{center: [1, 0], height: 0.001, sigma: [0.3, 0.3], "
                     "width: 2}]}\n")
                .find("width: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of("format_version: 1\n"
                     "field: {bumps: [{height: 0.001, sigma: [0.3, 0.3]}]}\n")
                .find("center"),
            std::string::npos);
  std::string many = "format_version: 1\nfield:\n  bumps:\n";
  for (std::size_t i = 0; i <= kMaxPlantBumps; ++i)
    many += "    - {center: [1, 0], height: 0.001, sigma: [0.3, 0.3]}\n";
  EXPECT_NE(error_of(many).find("at most"), std::string::npos);
}

TEST(Plant, ContentHashIsFnv1a) {
  EXPECT_EQ(content_hash(""), "cbf29ce484222325");
  EXPECT_EQ(content_hash("a"), "af63dc4c8601ec8c");  // the published FNV-1a 64 test vector
}

}  // namespace
}  // namespace mg::plant
