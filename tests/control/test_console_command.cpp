#include "control/console_command.hpp"

#include <random>

#include <gtest/gtest.h>

namespace mg::control {
namespace {

template <class T>
T parsed(std::string_view line) {
  const ConsoleParse p = parse_console_line(line);
  EXPECT_TRUE(p.ok()) << line << ": " << p.error;
  EXPECT_TRUE(std::holds_alternative<T>(p.command)) << line;
  return std::holds_alternative<T>(p.command) ? std::get<T>(p.command) : T{};
}

TEST(ConsoleCommand, ParsesEveryCommand) {
  parsed<IdleCmd>("idle");
  parsed<RestCmd>("  rest   # comment");
  parsed<HitCmd>("hit");
  EXPECT_DOUBLE_EQ(parsed<AngleCmd>("angle -0.25").radians, -0.25);
  EXPECT_DOUBLE_EQ(parsed<SpeedCmd>("speed 1.5").metres_per_second, 1.5);
  parsed<AutoCmd>("auto");
  const HoleCmd h = parsed<HoleCmd>("hole 2.0 0.1");
  EXPECT_DOUBLE_EQ(h.x, 2.0);
  EXPECT_DOUBLE_EQ(h.y, 0.1);
  parsed<ResetCmd>("reset");
  const LoadCmd l = parsed<LoadCmd>("load params models/gpr.json");
  EXPECT_EQ(l.what, LoadCmd::What::kParams);
  EXPECT_EQ(l.path, "models/gpr.json");
  EXPECT_EQ(parsed<LoadCmd>("load hitting h.json").what, LoadCmd::What::kHitting);
  EXPECT_EQ(parsed<RecordCmd>("record on run.csv").path, "run.csv");
  EXPECT_FALSE(parsed<RecordCmd>("record off").on);
  EXPECT_DOUBLE_EQ(parsed<WaitCmd>("wait 2").seconds, 2.0);
  parsed<StatusCmd>("status");
  parsed<HelpCmd>("help");
  parsed<QuitCmd>("quit");
  parsed<EmptyLine>("");
  parsed<EmptyLine>("   # only a comment");
}

TEST(ConsoleCommand, BadLinesAreAnsweredNotFatal) {
  for (const char* line : {"jump", "angle", "angle abc", "angle nan", "angle inf", "speed 1 2",
                           "hole 1", "hole 1 y", "load", "load model x", "record", "record on",
                           "record maybe x", "wait -1", "wait 1e9", "hit now", "status 1"}) {
    const ConsoleParse p = parse_console_line(line);
    EXPECT_FALSE(p.ok()) << line;
    EXPECT_EQ(p.error.find('\n'), std::string::npos) << line;
  }
  EXPECT_NE(parse_console_line("jump").error.find("help"), std::string::npos);
}

TEST(ConsoleCommand, RandomBytesNeverCrash) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 20000; ++i) {
    std::string line(rng() % 40, ' ');
    for (char& c : line) c = static_cast<char>(rng() % 128);
    const ConsoleParse p = parse_console_line(line);
    EXPECT_TRUE(p.ok() || !p.error.empty());
  }
}

// A 100,000-character unknown command was echoed whole in the answer.
TEST(ConsoleCommand, AnUnknownCommandIsQuotedShortOnOneLine) {
  const ConsoleParse p = parse_console_line(std::string(100000, 'x'));
  EXPECT_EQ(p.error,
            "unknown command '" + std::string(40, 'x') + "... (100000 characters)' (type help)");
  EXPECT_EQ(parse_console_line("fly\x1b[2J").error, "unknown command 'fly?[2J' (type help)");
}

}  // namespace
}  // namespace mg::control
