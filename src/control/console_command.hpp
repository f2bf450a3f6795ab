#pragma once
/// The console's command language (thesis 4.2.2 "user update"; RobotToolKit-like).
///
/// One command per line; words separated by blanks; `#` starts a comment. Parsing is pure and
/// never throws: a bad line gives an error message for the console to print, never a crash.
#include <string>
#include <string_view>
#include <variant>

namespace mg::control {

struct IdleCmd {};
struct RestCmd {};
struct HitCmd {};
struct AngleCmd {
  double radians;
};
struct SpeedCmd {
  double metres_per_second;
};
struct AutoCmd {};
struct HoleCmd {
  double x, y;
};
struct ResetCmd {};
struct LoadCmd {
  enum class What { kHitting, kParams } what;
  std::string path;
};
struct RecordCmd {
  bool on;
  std::string path;  ///< empty for `record off`
};
struct WaitCmd {
  double seconds;
};
struct StatusCmd {};
struct HelpCmd {};
struct QuitCmd {};
struct EmptyLine {};

using ConsoleCommand =
    std::variant<EmptyLine, IdleCmd, RestCmd, HitCmd, AngleCmd, SpeedCmd, AutoCmd, HoleCmd,
                 ResetCmd, LoadCmd, RecordCmd, WaitCmd, StatusCmd, HelpCmd, QuitCmd>;

struct ConsoleParse {
  ConsoleCommand command;
  std::string error;  ///< empty when the line parsed
  bool ok() const { return error.empty(); }
};

/// Parses one console line. Numbers must be finite; `wait` takes 0..3600 s.
ConsoleParse parse_console_line(std::string_view line);

/// One line per command, for `help`.
std::string_view console_help();

}  // namespace mg::control
