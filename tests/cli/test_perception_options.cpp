// `--perception truth|camera [--rig R] [--calibration C]` on every command that plays the arm's
// putts (putt, evaluate, self-teach, play, identify): one parser, the same one-line errors with
// exit 2, found before any putt and without a display.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const auto dir = fs::temp_directory_path() / ("mg_perception_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

TEST(PerceptionOptions, BadValuesAreOneLineAndExitTwoOnEveryCommand) {
  // A model for evaluate (three rows of a data set).
  const auto data = scratch("d.csv"), model = scratch("m.json");
  std::ofstream(data)
      << "xi_x,xi_y,angle,speed\n1.8,0,0.01,1.5\n2,0.1,0.05,1.6\n2.2,-0.1,-0.02,1.7\n";
  ASSERT_EQ(run_minigolf("train " + data.string() + " -o " + model.string()).exit_code, 0);
  // A course of one flat hole for play; a rig whose first camera looks away from the lane.
  const auto course = scratch("course.yaml");
  std::ofstream(course) << "format_version: 1\nname: one\nholes:\n  - {field: flat, par: 2}\n";
  const auto away = scratch("away.yaml");
  std::ofstream(away) << R"(format_version: 1
name: away
cameras:
  - {name: a, position: [0.2, 1.0, 2.2], look_at: [1.2, 5, 5], fovy_deg: 50, width: 64,
     height: 48, rate_hz: 60}
  - {name: b, position: [2.2, 1.0, 2.2], look_at: [1.2, 0, 0], fovy_deg: 50, width: 64,
     height: 48, rate_hz: 60}
)";
  const std::vector<std::string> commands = {
      "putt --angle 0 --speed 1.5",
      "evaluate --field flat --situations 2 --no-oracle --model " + model.string(),
      "self-teach --field flat --budget 2 -o " + scratch("out.json").string(),
      "play --course " + course.string() + " --budget 1",
      "identify --field flat --putts 1",
  };
  struct Case {
    std::string args, needle;
  };
  const std::vector<Case> cases = {
      {"--perception eyes", "--perception"},
      {"--perception camera --rig /no/such/rig.yaml", "/no/such/rig.yaml"},
      {"--perception camera --calibration /no/such/calibration.yaml", "/no/such/calibration.yaml"},
      {"--perception camera --rig " + away.string(), "camera 'a' sees no part of the lane"},
      {"--rig stereo", "--rig: only with --perception camera"},
      {"--perception truth --calibration x.yaml", "--calibration: only with --perception camera"},
  };
  // Every case on one command; an unknown name and a missing rig on every command (one parser).
  const auto expect_refused = [](const std::string& args, const std::string& needle) {
    const auto r = run_minigolf(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.out.find("SUNK"), std::string::npos) << args;  // no putt was played
  };
  for (const auto& c : cases) expect_refused(commands[1] + " " + c.args, c.needle);
  for (const auto& command : commands)
    for (std::size_t k = 0; k < 2; ++k)
      if (command != commands[1]) expect_refused(command + " " + cases[k].args, cases[k].needle);
  fs::remove_all(scratch("").parent_path());
}

}  // namespace
}  // namespace mg::cli::testing
