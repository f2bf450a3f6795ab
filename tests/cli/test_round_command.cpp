// `minigolf play`: a round's JSON and CSV, the comparison table, bad course files.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../slow_test.hpp"
#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

std::filesystem::path write_course(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "mg_round_cli";
  std::filesystem::create_directories(dir);
  const auto p = dir / name;
  std::ofstream(p) << text;
  return p;
}

const char* kTiny = R"(format_version: 1
name: tiny
max_strokes: 4
holes:
  - {field: flat, tee: [0.3, -0.1], hole: [1.5, 0.2], par: 2}
  - {field: regular-hill, par: 2}
)";

TEST(PlayCli, JsonHasEveryHoleAndPuttAndTheCsvEveryStroke) {
  const auto course = write_course("tiny.yaml", kTiny);
  const auto csv = course.parent_path() / "tiny.csv";
  const auto r = run_minigolf("play --course " + course.string() +
                              " --player oracle --seed 3 --json -o " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["course"], "tiny");
  ASSERT_EQ(j["holes"].size(), 2u);
  int total = 0, putts = 0;
  for (const auto& h : j["holes"]) {
    EXPECT_TRUE(h["sunk"].get<bool>());
    EXPECT_LE(h["strokes"].get<int>(), 4);
    total += h["strokes"].get<int>();
    putts += static_cast<int>(h["putts"].size());
    for (const auto& p : h["putts"])
      for (const char* key : {"ball", "angle", "speed", "rest", "sunk"})
        EXPECT_TRUE(p.contains(key)) << key;
  }
  EXPECT_EQ(j["total_strokes"].get<int>(), total);
  EXPECT_EQ(j["total_par"].get<int>(), 4);
  EXPECT_EQ(j["learning_putts"].get<int>(), 0);
  std::ifstream in(csv);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(count_lines(text), 1 + putts);
}

TEST(PlayCli, CompareTabulatesEveryPlayerOverSeeds) {
  MG_SLOW_TEST();
  const auto course = write_course("one.yaml", R"(format_version: 1
name: one
holes:
  - {field: flat, tee: [0.3, -0.1], hole: [1.2, 0.1], par: 2}
)");
  const auto r =
      run_minigolf("play --course " + course.string() + " --compare --seeds 2 --budget 3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* row :
       {"| robot |", "| oracle |", "| exact-oracle |", "| greedy |", "vs oracle", "hole-in-one"})
    EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
}

TEST(PlayCli, TheRobotPlaysItsLearnedModelWhereItSinks) {
  // The thesis's flat model (its shipped data set: xi_y -> angle at a fixed club speed), played
  // from a tee moved by (0.3, 0.1): on a level lane the situation is hole - ball.
  const auto dir = std::filesystem::temp_directory_path() / "mg_round_cli";
  std::filesystem::create_directories(dir);
  const auto model = dir / "flat-model.json";
  const auto data = std::filesystem::path(MINIGOLF_SOURCE_DIR) / "data" / "datasets" / "flat.csv";
  ASSERT_EQ(run_minigolf("train --method gpr " + data.string() + " -o " + model.string()).exit_code,
            0);
  const auto course = write_course("model.yaml", R"(format_version: 1
name: model
holes:
  - {field: flat, tee: [0.3, 0.1], hole: [2.3, 0.2], par: 2}
)");
  const auto r = run_minigolf("play --course " + course.string() + " --seed 2 --budget 4 --json " +
                              "--model flat=" + model.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& first = j["holes"][0]["putts"][0];
  EXPECT_TRUE(first["model"].get<bool>()) << first;
  EXPECT_TRUE(j["holes"][0]["sunk"].get<bool>());
  EXPECT_EQ(j["learning_putts"].get<int>(), 4);
  const std::vector<std::string> bad_specs{"flat", "=x.json",
                                           "flat=", "no-such-field=" + model.string(),
                                           "flat=" + (dir / "missing.json").string()};
  for (const std::string& bad : bad_specs) {
    const auto e = run_minigolf("play --course " + course.string() + " --model " + bad);
    EXPECT_EQ(e.exit_code, 2) << bad << ": " << e.err;
    EXPECT_EQ(count_lines(e.err), 1) << bad << ": " << e.err;
  }
  const auto e = run_minigolf("play --course " + course.string() +
                              " --player oracle --model flat=" + model.string());
  EXPECT_EQ(e.exit_code, 2);
  EXPECT_NE(e.err.find("--model"), std::string::npos) << e.err;
}

TEST(PlayCli, BadCoursesAreOneLineErrorsWithExitTwo) {
  const auto inside = write_course("inside.yaml", R"(format_version: 1
name: bad
holes:
  - {field: bank-shot, hole: [1.0, 0.05], par: 2}
)");
  const auto par = write_course("par.yaml", R"(format_version: 1
name: bad
holes:
  - {field: flat, par: 0}
)");
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"play --course no-such-course", "no-such-course"},
      {"play --course " + inside.string(), "holes[0]"},
      {"play --course " + par.string(), "holes[0].par"},
      {"play --course thesis --player tiger", "--player"},
      {"play --course thesis --budget 0", "--budget"},
      {"play --course thesis,flat", "one course"},
      {"play --course thesis --compare --json", "--json"},
  };
  for (const auto& c : cases) {
    const auto r = run_minigolf(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << c.args << ": " << r.err;
  }
}

}  // namespace
}  // namespace mg::cli::testing
