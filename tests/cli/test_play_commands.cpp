// `minigolf sweep | collect | evaluate | reproduce` end to end, on a user's field with its own
// situations, and their one-line errors.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

namespace fs = std::filesystem;

fs::path temp(const std::string& name) {
  return fs::temp_directory_path() / ("mg_play_cli_" + std::to_string(::getpid()) + "_" + name);
}

std::string user_field() {
  return std::string(MINIGOLF_TEST_DATA_DIR) + "/fields/user-tilted.yaml";
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void expect_one_line_error(const std::string& args, const std::string& needle) {
  const auto r = run_minigolf(args);
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
}

TEST(PlayCommands, UserFieldRunsThroughCollectTrainAndEvaluate) {
  const auto data = temp("user.csv"), model = temp("user.json");
  auto r = run_minigolf("collect --field " + user_field() + " -o " + data.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("collected 4 of 4"), std::string::npos) << r.out;
  r = run_minigolf("train --method gpr " + data.string() + " -o " + model.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_minigolf("evaluate --field " + user_field() + " --model " + model.string() +
                   " --situations 4 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"success_ratio", "ci95", "oracle_ceiling", "situations", "sunk", "rows"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["situations"], 4);
  EXPECT_EQ(j["rows"].size(), 4u);
  EXPECT_EQ(j["oracle_ceiling"].get<double>(), 1.0);  // the list's own points: all collected
  EXPECT_GE(j["sunk"].get<int>(), 3) << r.out;        // the test situations are the training points
  fs::remove(data);
  fs::remove(model);
}

TEST(PlayCommands, SweepWritesTheGridCsv) {
  const auto out = temp("sweep.csv");
  const auto r = run_minigolf(
      "sweep --field flat --hole 1.5,0 --angles -0.02:0.02:3 --speeds 1.8:2.2:2 --ball-only -o " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream in(slurp(out));
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("angle,speed,sunk,closest_approach,rest_x,rest_y", 0), 0u) << header;
  int rows = 0;
  for (std::string line; std::getline(in, line);) rows += !line.empty();
  EXPECT_EQ(rows, 6);
  fs::remove(out);
}

TEST(PlayCommands, BadInputsGetOneLineAndExitTwo) {
  const auto out = temp("bad.csv");
  expect_one_line_error("collect --field flat --strategy fastest -o " + out.string(),
                        "min-speed or min-angle");
  expect_one_line_error("collect --field flat --situations list: -o " + out.string(),
                        "--situations 'list:': list.points");
  expect_one_line_error("collect --field flat --situations line:2,0:2,5:3 -o " + out.string(),
                        "outside the lane");
  expect_one_line_error("collect --field flat --balls box:0,0.4:-0.2 -o " + out.string(),
                        "--balls 'box:0,0.4:-0.2'");
  expect_one_line_error("collect --field flat --balls list:0.5,0.7 -o " + out.string(),
                        "expected a ball on the lane");
  expect_one_line_error(
      "self-teach --field flat --budget 5 --balls list:0.5,0.7 -o " + out.string(),
      "expected a ball on the lane");
  expect_one_line_error("sweep --field flat --angles 0:0.1 --speeds 1:2:3 -o " + out.string(),
                        "LO:HI:N");
  expect_one_line_error("sweep --field flat --angles 0:0.1:3 --speeds 1:9:3 -o " + out.string(),
                        "safe envelope");
  // A model whose inputs do not match a situation.
  const auto data = temp("d.csv"), model = temp("m.json");
  { std::ofstream(data) << "dist,angle,speed\n1,0.1,1.5\n2,0.2,1.6\n3,0.25,1.7\n"; }
  ASSERT_EQ(
      run_minigolf("train --inputs dist " + data.string() + " -o " + model.string()).exit_code, 0);
  expect_one_line_error("evaluate --field flat --model " + model.string(),
                        "does not match a situation");
  // A NaN in a data set.
  { std::ofstream(data) << "xi_x,xi_y,angle,speed\n2,0,nan,1.5\n2,0.1,0.05,1.5\n"; }
  expect_one_line_error("train " + data.string() + " -o " + model.string(), "finite");
  expect_one_line_error(
      "reproduce --quick --fields flat --datasets /nonexistent -o " + temp("r").string(),
      "missing");
  expect_one_line_error("collect --field nowhere -o " + out.string(), "unknown field");
  {  // found only after trying: progress lines first, then the one error line
    const auto r = run_minigolf(
        "collect --field flat --situations line:2.64,-0.1:2.64,0.1:2 --max-full-putts 6 -o " +
        out.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("minigolf: error: collect: no sinking putt in any of the 2 situations"),
              std::string::npos)
        << r.err;
    EXPECT_NE(slurp(out).find("# unplayable: index=1"),
              std::string::npos);  // the attempts are kept
  }
  {  // self-teach: a bad budget, and a region no putt reaches (progress lines, then one error line)
    expect_one_line_error("self-teach --field flat --budget 0 -o " + model.string(),
                          "budget: expected 1..100000");
    expect_one_line_error("self-teach --field flat --budget -3 -o " + model.string(),
                          "budget: expected 1..100000");
    expect_one_line_error("self-teach --field nowhere --budget 3 -o " + model.string(),
                          "unknown field");
    const auto r = run_minigolf(
        "self-teach --field flat --situations line:2.64,-0.1:2.64,0.1:2 --budget 3 -o " +
        model.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("minigolf: error: self-teach: field 'flat': 0 hindsight label(s)"),
              std::string::npos)
        << r.err;
    expect_one_line_error(
        "evaluate --field flat --model " + model.string() + " --save-model " + out.string(),
        "only with --learn");
  }
  fs::remove(data);
  fs::remove(model);
  fs::remove_all(temp("r"));
  fs::remove(out);
}

TEST(PlayCommands, SelfTeachWritesAModelThatEvaluateAndPredictPlayUnchanged) {
  const auto model = temp("self.json"), log = temp("self.csv");
  auto r = run_minigolf("self-teach --field flat --budget 6 --seed 2 --log " + log.string() +
                        " -o " + model.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("self-taught flat in 6 full-system putts"), std::string::npos) << r.out;
  EXPECT_EQ(count_lines(slurp(log)), 7);  // header + one row per putt
  r = run_minigolf("evaluate --field flat --model " + model.string() +
                   " --situations 10 --no-oracle --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GE(j["sunk"].get<int>(), 8) << r.out;  // measured 10 of 10
  r = run_minigolf("evaluate --field flat --model " + model.string() +
                   " --situations 4 --learn --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["labels_added"].size(), 4u);
  fs::remove(model);
  fs::remove(log);
}

}  // namespace
}  // namespace mg::cli::testing
