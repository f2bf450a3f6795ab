// `minigolf study launch-error` end to end (few hits: every hit is a full arm putt).
#include <unistd.h>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("mg_study_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(StudyCommand, WritesCsvAndMarkdownAndPrintsTheTable) {
  const auto dir = temp_dir("table");
  const auto r =
      run_minigolf("study launch-error --angles-deg -10,0 --hits 2 --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(count_lines(r.err), 4) << r.err;  // progress: one line per hit
  EXPECT_NE(r.out.find("| angle [deg] | n | mean error [deg] | std [deg] |"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("| -10 | 2 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| 0 | 2 |"), std::string::npos) << r.out;
  EXPECT_EQ(read(dir / "launch_error.md"), r.out);
  const std::string csv = read(dir / "launch_error.csv");
  EXPECT_EQ(count_lines(csv), 5) << csv;  // header + 2 angles x 2 hits
  EXPECT_EQ(csv.rfind("angle_deg,hit,seed,struck,", 0), 0u) << csv;
  EXPECT_FALSE(std::filesystem::exists(dir / "launch_error.png"));
  std::filesystem::remove_all(dir);
}

TEST(StudyCommand, JsonSummaryIsReproducibleAndZeroNoiseHasZeroStd) {
  const auto dir = temp_dir("json");
  const std::string args =
      "study launch-error --angles-deg 0 --hits 2 --torque-noise 0 "
      "--placement-noise 0 --json --out " +
      dir.string();
  const auto a = run_minigolf(args);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto j = nlohmann::json::parse(a.out);
  ASSERT_EQ(j["angles"].size(), 1u);
  EXPECT_EQ(j["angles"][0]["n"].get<int>(), 2);
  EXPECT_EQ(j["angles"][0]["std_error_deg"].get<double>(), 0.0);
  EXPECT_LT(std::abs(j["angles"][0]["mean_error_deg"].get<double>()), 0.5);
  EXPECT_EQ(j["seed"].get<std::uint64_t>(), 1u);
  EXPECT_EQ(run_minigolf(args).out, a.out);
  std::filesystem::remove_all(dir);
}

TEST(StudyCommand, BadOptionsGiveOneLineErrorAndExit2) {
  const auto dir = temp_dir("bad");
  for (const std::string& opt : {
           std::string("--hits 0"),
           std::string("--hits 2x"),
           std::string("--hits -1"),
           std::string("--speed abc"),
           std::string("--speed 9"),
           std::string("--speed nan"),
           std::string("--angles-deg 0,,5"),
           std::string("--angles-deg 90"),
           std::string("--angles-deg 1e"),
           std::string("--torque-noise -0.1"),
           std::string("--torque-noise 2"),
           std::string("--placement-noise 1"),
           std::string("--seed -3"),
           std::string("--seed 1.5"),
           std::string("--field mars"),
       }) {
    const auto r = run_minigolf("study launch-error " + opt + " --out " + dir.string());
    EXPECT_EQ(r.exit_code, 2) << opt << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << opt << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << opt;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "launch_error.csv"));
  EXPECT_NE(run_minigolf("study").exit_code, 0);  // needs launch-error
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mg::cli::testing
