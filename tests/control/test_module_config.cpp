// Module config: defaults valid, YAML overrides, every bad field named.
#include "control/module_config.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg::control {
namespace {

TEST(ModuleConfig, DefaultsAreValid) { EXPECT_NO_THROW(ModuleConfig{}.validate()); }

TEST(ModuleConfig, YamlOverridesAndScalarGains) {
  const auto c = parse_module_config(
      "field: arctan\nmode: normal\nkp: 100\nkd: [1, 2, 3, 4, 5, 6, 7]\nfir_length: 7\n"
      "angle_max: 0.5\n",
      "test");
  EXPECT_EQ(c.field, "arctan");
  EXPECT_EQ(c.mode, ModuleMode::kNormal);
  for (double k : c.kp) EXPECT_EQ(k, 100.0);
  EXPECT_EQ(c.kd[6], 7.0);
  EXPECT_EQ(c.fir_length, 7);
  EXPECT_EQ(c.angle_max, 0.5);
  EXPECT_EQ(c.speed_max, ModuleConfig{}.speed_max);  // untouched keys keep their defaults
}

TEST(ModuleConfig, EmptyTextGivesDefaults) {
  EXPECT_EQ(parse_module_config("", "empty").fir_length, ModuleConfig{}.fir_length);
}

TEST(ModuleConfig, BadValuesNameTheirField) {
  const std::pair<const char*, const char*> cases[] = {
      {"fir_length: 0", "fir_length"},
      {"fir_length: 99", "fir_length"},
      {"kp: -1", "kp"},
      {"kd: [1, 2]", "kd"},
      {"speed_max: 5", "speed_max"},
      {"speed_min: .nan", "speed_min"},
      {"angle_min: 0.3", "angle_min"},
      {"mode: turbo", "mode"},
      {"core_rate: 300", "core_rate"},
      {"rest_offset: [0.1, 0, 0.1]", "rest_offset"},
      {"brake_time: 0", "brake_time"},
      {"typo_key: 1", "typo_key"},
      {"fir_length: many", "fir_length"},
      {"[1, 2", "YAML"},
  };
  for (const auto& [text, field] : cases) {
    try {
      parse_module_config(text, "cfg");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

TEST(ModuleConfig, GroupedKeysReadAsFlatOnesAndAWrongGroupIsNamed) {
  const auto flat = parse_module_config("kp: 100\nfield: arctan\nvision_port: 0\n", "flat");
  const auto grouped = parse_module_config(
      "controller: {kp: 100}\nsession: {field: arctan}\nvision: {vision_port: 0}\n", "grouped");
  EXPECT_EQ(flat, grouped);
  EXPECT_NE(flat, ModuleConfig{});
  const std::pair<const char*, const char*> cases[] = {
      {"controller: {field: arctan}", "belongs under 'session'"},
      {"vision: {kp: 1}", "belongs under 'controller'"},
      {"session: 3", "expected a mapping"},
      {"controller: {typo: 1}", "typo"},
      {"vision: {vision_port: 70000}", "vision_port"},
  };
  for (const auto& [text, message] : cases) {
    try {
      parse_module_config(text, "cfg");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

// A key twice kept the first; a second document was ignored.
TEST(ModuleConfig, DuplicateKeysAndSecondDocumentsAreRefused) {
  const std::pair<const char*, const char*> cases[] = {
      {"kp: 100\nkp: 200\n", "cfg: kp: duplicate key"},
      {"controller: {kp: 1, kp: 2}\n", "cfg: controller.kp: duplicate key"},
      {"kp: 100\n---\nkp: 200\n", "cfg: a second YAML document at line 2"},
  };
  for (const auto& [text, message] : cases) {
    try {
      parse_module_config(text, "cfg");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(message, 0), 0u) << e.what();
    }
  }
}

TEST(ModuleConfig, EachPartComparesOnlyItsOwnKeys) {
  ModuleConfig a, b;
  b.vision_port = 0;
  b.record = "x.csv";
  EXPECT_NE(a, b);
  EXPECT_EQ(static_cast<const ControllerConfig&>(a), static_cast<const ControllerConfig&>(b));
  b.kp[3] = 1.0;
  EXPECT_NE(static_cast<const ControllerConfig&>(a), static_cast<const ControllerConfig&>(b));
}

TEST(ModuleConfig, MissingFileIsAnIoError) {
  EXPECT_THROW(load_module_config("/nonexistent/module.yaml"), IoError);
}

}  // namespace
}  // namespace mg::control
