// `--plant` on the commands, `plant random` and `plant show`, and bad plant files (exit 2, one
// line).
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

std::filesystem::path scratch(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("mg_plant_cli_" + std::to_string(::getpid()) + "_" + name);
}

std::filesystem::path write(const std::string& name, const std::string& text) {
  const auto p = scratch(name);
  std::ofstream(p) << text;
  return p;
}

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(PlantCommands, RandomPlantsAreFilesThatEveryCommandReads) {
  const auto p = scratch("random.yaml");
  const auto r = run_minigolf("plant random --seed 4 -o " + p.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto again = scratch("random2.yaml");
  ASSERT_EQ(run_minigolf("plant random --seed 4 -o " + again.string()).exit_code, 0);
  std::ifstream a(p), b(again);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}),
            std::string(std::istreambuf_iterator<char>(b), {}));
  const auto show = run_minigolf("plant show " + p.string() + " --field regular-hill");
  ASSERT_EQ(show.exit_code, 0) << show.err;
  EXPECT_NE(show.out.find("rolling resistance"), std::string::npos);
  const auto putt =
      run_minigolf("putt --field flat --angle 0 --speed 1.6 --json --plant " + p.string());
  ASSERT_EQ(putt.exit_code, 0) << putt.err;
  const auto j = nlohmann::json::parse(putt.out);
  EXPECT_EQ(j["plant"]["path"], p.string());
  EXPECT_EQ(j["plant"]["hash"].get<std::string>().size(), 16u);
  const auto none =
      nlohmann::json::parse(run_minigolf("putt --field flat --angle 0 --speed 1.6 --json").out);
  EXPECT_TRUE(none["plant"].is_null());
  std::filesystem::remove(p);
  std::filesystem::remove(again);
}

TEST(PlantCommands, AnEmptyPlantGivesTheSameOutcome) {
  const auto empty = write("empty.yaml", "format_version: 1\n");
  const auto with = nlohmann::json::parse(
      run_minigolf("putt --field regular-hill --angle 0.01 --speed 1.7 --json --plant " +
                   empty.string())
          .out);
  const auto without = nlohmann::json::parse(
      run_minigolf("putt --field regular-hill --angle 0.01 --speed 1.7 --json").out);
  for (const char* key : {"rest_position", "closest_approach", "launch", "club", "steps", "sunk"})
    EXPECT_EQ(with[key], without[key]) << key;
  std::filesystem::remove(empty);
}

TEST(PlantCommands, BadPlantsAreOneLineAndExitTwo) {
  const auto unknown = write("unknown.yaml", "format_version: 1\nfield:\n  grass: 0.2\n");
  const auto range = write("range.yaml", "format_version: 1\narm:\n  club_speed_scale: 9\n");
  // A 0-byte plant and one without its version were the identity.
  const auto zero = write("zero.yaml", "");
  const auto unversioned = write("unversioned.yaml", "arm:\n  club_speed_scale: 0.9\n");
  for (const std::string& cmd : std::vector<std::string>{
           "putt --field flat --angle 0 --speed 1.6 --plant " + unknown.string(),
           "putt --field flat --angle 0 --speed 1.6 --ball-only --plant " + range.string(),
           "sweep --field flat --angles 0:0:1 --speeds 1.6:1.6:1 -o " +
               scratch("sweep.csv").string() + " --plant " + unknown.string(),
           "putt --field flat --angle 0 --speed 1.6 --plant " + zero.string(),
           "putt --field flat --angle 0 --speed 1.6 --ball-only --plant " + unversioned.string(),
           "evaluate --field flat --model /no/model.json --plant " + unknown.string(),
           "putt --field flat --angle 0 --speed 1.6 --plant /no/such/plant.yaml",
           "putt --field flat --angle 0 --speed 1.6 --plant /tmp",
           "plant show " + range.string()}) {
    const auto r = run_minigolf(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1) << cmd << "\n" << r.err;
  }
  const auto r =
      run_minigolf("putt --field flat --angle 0 --speed 1.6 --plant " + unknown.string());
  EXPECT_NE(r.err.find("field.grass: unknown key"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(unknown.string()), std::string::npos) << r.err;
  EXPECT_NE(run_minigolf("plant show " + zero.string()).err.find("empty plant file"),
            std::string::npos);
  EXPECT_NE(run_minigolf("plant show " + unversioned.string()).err.find("format_version: missing"),
            std::string::npos);
  for (const auto& p : {unknown, range, zero, unversioned}) std::filesystem::remove(p);
}

}  // namespace
}  // namespace mg::cli::testing
