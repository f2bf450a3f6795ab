#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

TEST(PuttCommand, JsonHasTheOutcomeKeys) {
  const auto r =
      run_minigolf("putt --field flat --hole 1.5,0 --angle 0 --speed 2.0 --ball-only --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["sunk"].is_boolean());
  EXPECT_EQ(j["rest_position"].size(), 2u);
  EXPECT_GE(j["closest_approach"].get<double>(), 0.0);
  EXPECT_GT(j["duration"].get<double>(), 0.0);
}

TEST(PuttCommand, AimedPuttOnTheFlatSinks) {
  // Rolls (5/7) v0 after the slide; a 1.8 m/s launch arrives slowly at 1.2 m.
  const auto r =
      run_minigolf("putt --field flat --hole 1.2,0 --angle 0 --speed 1.8 --ball-only --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out)["sunk"].get<bool>()) << r.out;
}

// The case: the ball moved to (1.0, 0.3) on flat, the base beside it facing the hole.
TEST(PuttCommand, TheArmPuttsFromWhereverTheBallLies) {
  const auto r = run_minigolf("putt --field flat --ball 1.0,0.3 --angle 0 --speed 0.6 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["ball"], nlohmann::json::parse("[1.0, 0.3]"));
  EXPECT_NEAR(j["aim"].get<double>(), std::atan2(-0.3, 1.0), 1e-12);  // towards the hole (2, 0)
  const auto rest = j["rest_position"].get<std::array<double, 2>>();
  EXPECT_GT(rest[0], 1.1) << r.out;
  EXPECT_LT(rest[1], 0.3) << r.out;
  const auto off = run_minigolf("putt --field flat --ball 9,0 --angle 0 --speed 0.6");
  EXPECT_EQ(off.exit_code, 2);
  EXPECT_NE(off.err.find("--ball"), std::string::npos) << off.err;
  const auto aim = run_minigolf("putt --field flat --ball-only --aim 1 --angle 0 --speed 0.6");
  EXPECT_EQ(aim.exit_code, 2);
}

// --world: the angle is a world direction; the base faces +x within the fixed arm's reach and
// turns beyond it (the stance rule of learned hits).
TEST(PuttCommand, AWorldDirectionPicksItsStance) {
  const auto within = run_minigolf(
      "putt --field flat --ball 1.0,0.3 --world --angle 0.2 "
      "--speed 0.6 --json");
  ASSERT_EQ(within.exit_code, 0) << within.err;
  EXPECT_EQ(nlohmann::json::parse(within.out)["aim"].get<double>(), 0.0);
  const auto back = run_minigolf(
      "putt --field flat --ball 1.0,0.3 --world --angle 2.8 "
      "--speed 0.6 --json");
  ASSERT_EQ(back.exit_code, 0) << back.err;
  const auto j = nlohmann::json::parse(back.out);
  EXPECT_NEAR(j["aim"].get<double>(), 2.8, 1e-12);
  EXPECT_NEAR(j["launch"]["angle"].get<double>(), 2.8, 0.02) << back.out;  // a world angle
  EXPECT_LT(j["rest_position"][0].get<double>(), 1.0) << back.out;
  for (const char* bad : {"putt --field flat --world --aim 1 --angle 0 --speed 0.6",
                          "putt --field flat --world --ball-only --angle 0 --speed 0.6",
                          "putt --field flat --world --angle 0 --speed 9"}) {
    const auto r = run_minigolf(bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

TEST(PuttCommand, TrajectoryCsvHasTheDocumentedHeader) {
  const auto path = std::filesystem::temp_directory_path() / "mg_traj.csv";
  const auto r = run_minigolf(
      "putt --field arctan --angle 0.1 --speed 1.5 --ball-only --trajectory " + path.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t,x,y,z,vx,vy,vz");
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  EXPECT_GT(rows, 10);
  std::filesystem::remove(path);
}

TEST(PuttCommand, ArmPuttWritesTheTrajectoryFromTheFirstContactAndTheSameOutcome) {
  const auto path = std::filesystem::temp_directory_path() / "mg_arm_traj.csv";
  std::filesystem::remove(path);
  const std::string args = "putt --field flat --angle 0.01 --speed 1.6 --json";
  const auto plain = run_minigolf(args);
  const auto recorded = run_minigolf(args + " --trajectory " + path.string());
  ASSERT_EQ(recorded.exit_code, 0) << recorded.err;
  auto a = nlohmann::json::parse(plain.out), b = nlohmann::json::parse(recorded.out);
  a.erase("timing"), b.erase("timing");  // wall-clock times of the core update
  EXPECT_EQ(a, b) << "recording the trajectory changes the putt";
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t,x,y,z,vx,vy,vz");
  std::vector<std::array<double, 3>> rows;  // t, x, y
  for (std::string line; std::getline(in, line);) {
    std::array<double, 3> r{};
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &r[0], &r[1], &r[2]), 3) << line;
    rows.push_back(r);
  }
  // flat: tee at the origin; the duration counts from the first contact, as t does.
  ASSERT_GT(rows.size(), 50u);
  EXPECT_EQ(rows.front()[0], 0.0);
  EXPECT_LT(std::hypot(rows.front()[1], rows.front()[2]), 0.01);
  EXPECT_NEAR(rows.back()[0], a["duration"].get<double>(), 1e-9);
  EXPECT_NEAR(rows.back()[1], a["rest_position"][0].get<double>(), 0.01);
  for (std::size_t i = 1; i < rows.size(); ++i) ASSERT_GT(rows[i][0], rows[i - 1][0]) << i;
  std::filesystem::remove(path);
}

TEST(PuttCommand, ReadableLineWithoutJson) {
  const auto r = run_minigolf("putt --field multiple-hills --angle 0 --speed 2.5 --ball-only");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(count_lines(r.out), 1);
  EXPECT_NE(r.out.find("multiple-hills"), std::string::npos);
}

TEST(PuttCommand, BadInputGivesOneLineErrorAndNonZeroExit) {
  for (const std::string& args : {
           std::string("putt --field flat --angle nan --speed 1 --ball-only"),
           std::string("putt --field flat --angle 0 --speed inf --ball-only"),
           std::string("putt --field flat --angle 0 --speed -2 --ball-only"),
           std::string("putt --field flat --angle 0 --speed 99 --ball-only"),
           std::string("putt --field flat --hole 9,0 --angle 0 --speed 1 --ball-only"),
           std::string("putt --field flat --hole 1,x --angle 0 --speed 1 --ball-only"),
           std::string("putt --field flat --hole 1 --angle 0 --speed 1 --ball-only"),
           std::string("putt --field mars --angle 0 --speed 1 --ball-only"),
       }) {
    const auto r = run_minigolf(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
  }
  EXPECT_NE(run_minigolf("putt --field flat --speed 1 --ball-only").exit_code,
            0);  // missing --angle
  // Without --ball-only the arm hits the ball (the default since the control module).
  EXPECT_EQ(run_minigolf("putt --field flat --angle 0 --speed 1").exit_code, 0);
}

TEST(PuttCommand, SamePuttPrintsTheSameBits) {
  const std::string args = "putt --field regular-hill --angle 0.02 --speed 2.4 --ball-only --json";
  EXPECT_EQ(run_minigolf(args).out, run_minigolf(args).out);
}

}  // namespace
}  // namespace mg::cli::testing
