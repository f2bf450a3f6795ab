#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

TEST(FieldCommand, ListNamesTheFourThesisFields) {
  const auto r = run_minigolf("field list");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"flat", "multiple-hills", "regular-hill", "arctan"})
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
}

TEST(FieldCommand, ShowJsonHasTheResolvedField) {
  const auto r = run_minigolf("field show regular-hill --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key :
       {"rolling_resistance", "ball_radius", "hole_diameter", "hole_depth", "tee", "bounds"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["bounds"].size(), 4u);
  EXPECT_EQ(j["tee"].size(), 2u);
  EXPECT_GT(j["hole_diameter"].get<double>(), 2.0 * j["ball_radius"].get<double>());
}

TEST(FieldCommand, UserFileByPath) {
  const auto path = std::filesystem::temp_directory_path() / "mg_user_field.yaml";
  std::ofstream(path) << R"(format_version: 1
name: my-ramp
lane: {bounds: [-0.3, 2.7, -0.6, 0.6]}
tee: [0.0, 0.0]
hole: {position: [2.0, 0.2]}
rolling_resistance: 0.1
surface: [{type: plane, slope_y: 0.02}]
)";
  const auto r = run_minigolf("field show " + path.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["name"], "my-ramp");
  const auto putt =
      run_minigolf("putt --ball-only --field " + path.string() + " --angle 0 --speed 1 --json");
  EXPECT_EQ(putt.exit_code, 0) << putt.err;
  std::filesystem::remove(path);
}

TEST(FieldCommand, BadFieldsGiveOneLineErrors) {
  const auto path = std::filesystem::temp_directory_path() / "mg_bad_field.yaml";
  std::ofstream(path) << "format_version: 1\nlane: {bounds: [0, 1]}\n";
  for (const std::string& arg :
       {std::string("nowhere"), std::string("/nonexistent/x.yaml"), path.string()}) {
    const auto r = run_minigolf("field show " + arg);
    EXPECT_EQ(r.exit_code, 2) << arg;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("error"), std::string::npos) << r.err;
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace mg::cli::testing
