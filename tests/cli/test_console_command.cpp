// `minigolf console` end to end: a script on standard input, bad configuration, bad flags.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "run_command.hpp"

namespace mg::cli::testing {
namespace {

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() /
                 ("mg_console_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(ConsoleCommand, ScriptOnStandardInputDrivesTheArm) {
  const auto script = write_temp(
      "script.txt",
      "# a scripted session\nrest\nwait 1\nangle 0.05\nspeed 1.0\nhit\nwait 3\nstatus\nquit\n");
  const CommandResult r = run_minigolf("console < " + script.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* expected :
       {"Idle -> Rest", "Rest -> Hitting", "Hitting -> Braking: the ball was hit",
        "Braking -> Idle", "state Idle", "bye"})
    EXPECT_NE(r.out.find(expected), std::string::npos) << expected << "\n" << r.out;
  std::filesystem::remove(script);
}

TEST(ConsoleCommand, EndOfInputQuits) {
  const CommandResult r = run_minigolf("console --script /dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("end of input: quit"), std::string::npos) << r.out;
}

TEST(ConsoleCommand, BadConfigurationIsOneLineAndExitTwo) {
  const auto bad_value = write_temp("bad_value.yaml", "kp: -3\n");
  const auto bad_key = write_temp("bad_key.yaml", "kpp: 3\n");
  for (const std::string& args :
       {"console --config " + bad_value.string(), "console --config " + bad_key.string(),
        std::string("console --config /nonexistent.yaml"), std::string("console --field nowhere"),
        std::string("console --mode fast"), std::string("console --vision-sim"),
        std::string("console --script /nonexistent-script")}) {
    const CommandResult r = run_minigolf(args + " < /dev/null");
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
  }
  std::filesystem::remove(bad_value);
  std::filesystem::remove(bad_key);
}

}  // namespace
}  // namespace mg::cli::testing
