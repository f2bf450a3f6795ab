// `minigolf identify`: a belief from the robot's own putts (docs/belief.md); bad inputs are one
// line and exit 2 before any putt is played.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() / ("mg_identify_cli_" + std::to_string(::getpid()) + "_" + name);
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(IdentifyCommand, WritesABeliefAndTakesItAsAPrior) {
  const fs::path out = scratch("belief.yaml");
  const std::string plant = std::string(MINIGOLF_SOURCE_DIR) + "/data/plants/real-wam.yaml";
  const auto r = run_minigolf("identify --field flat --plant " + plant +
                              " --putts 3 --seed 2 --json -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["putts"], 3);
  // The stand-in's grass is 12 % slower than the survey's 0.131; its tilt (0.002, -0.0015).
  EXPECT_NEAR(j["field"]["rolling_resistance"].get<double>(), 0.131 * 1.12, 0.03 * 0.131 * 1.12);
  EXPECT_NEAR(j["field"]["extra_slope"][1].get<double>(), -0.0015, 1e-3);
  EXPECT_GT(j["std"]["field"]["rolling_resistance"].get<double>(), 0.0);
  EXPECT_GT(j["std"]["arm"]["club_speed_scale"].get<double>(), 0.0);
  EXPECT_EQ(j["field"]["hole_offset"], nlohmann::json::array({0.0, 0.0}));  // not identified
  // The stand-in's green is one grass and one tilt: what the fit leaves is its 0.5 mm vision error.
  EXPECT_GT(j["residual"]["samples"].get<int>(), 100);
  EXPECT_NEAR(j["residual"]["rms_across"].get<double>(), 0.0005, 0.0002);
  EXPECT_FALSE(j["residual"]["structured"].get<bool>());
  const std::string text = read(out);
  EXPECT_NE(text.find("format_version: 1"), std::string::npos) << text;
  EXPECT_NE(text.find("std:"), std::string::npos) << text;
  EXPECT_NE(text.find("putts: 3"), std::string::npos) << text;
  // The belief as the prior of one more putt: it rests on 4 putts, the table says so.
  const auto again = run_minigolf("identify --field flat --plant " + plant +
                                  " --putts 1 --belief " + out.string());
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("belief after 4 putts"), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("hole_offset"), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("not identified"), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("residual:"), std::string::npos) << again.out;
  fs::remove(out);
}

TEST(IdentifyCommand, BadInputsAreOneLineAndExitTwoBeforeAnyPutt) {
  const fs::path fifo = scratch("fifo.yaml");
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path unknown = scratch("unknown.yaml");
  std::ofstream(unknown) << "putts: 2\nstd: {field: {grass: 1}}\n";
  const fs::path nan = scratch("nan.yaml");
  std::ofstream(nan) << "arm: {launch_angle_bias: .nan}\n";
  for (const std::string& args : std::vector<std::string>{
           "identify --field flat -o " + fifo.string(),
           "identify --field flat -o " + fs::temp_directory_path().string(),
           "identify --field flat --belief " + fifo.string(),
           "identify --field flat --belief " + fs::temp_directory_path().string(),
           "identify --field flat --belief " + unknown.string(),
           "identify --field flat --belief " + nan.string(),
           "identify --field flat --plant /no/such/plant.yaml",
           "identify --field no-such-field",
           "identify --field flat --balls box:9,10:0,1:2,2",
           "identify --field flat --putts 0",
           "identify --field flat --putts nan",
           // self-teach's identification: fewer putts than the budget, a belief to write only
           // with it, a writable place for it.
           "self-teach --field flat --budget 3 --identify 3 -o " + scratch("m.json").string(),
           "self-teach --field flat --budget 5 --belief-out " + scratch("b.yaml").string() +
               " -o " + scratch("m.json").string(),
           "self-teach --field flat --budget 5 --identify 2 --belief-out " + fifo.string() +
               " -o " + scratch("m.json").string(),
           // Revision while learning: a belief to write only when one is revised.
           "self-teach --field flat --budget 5 --prior /no/such/model.json --belief-out " +
               fifo.string() + " -o " + scratch("m.json").string(),
           "evaluate --field flat --model /no/such/model.json --no-revise",
           "evaluate --field flat --model /no/such/model.json --learn --no-revise --belief-out " +
               scratch("b.yaml").string(),
       }) {
    const auto r = run_minigolf(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("minigolf: error: ", 0), 0u) << args << "\n" << r.err;  // no progress
  }
  const auto r = run_minigolf("identify --field flat --belief " + unknown.string());
  EXPECT_NE(r.err.find("std.field.grass: unknown key"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(unknown.string()), std::string::npos) << r.err;
  fs::remove(fifo);
  fs::remove(unknown);
  fs::remove(nan);
}

}  // namespace
}  // namespace mg::cli::testing
