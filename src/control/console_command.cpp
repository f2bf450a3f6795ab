#include "control/console_command.hpp"

#include <charconv>
#include <cmath>
#include <vector>

namespace mg::control {
namespace {

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    if (i >= line.size() || line[i] == '#') break;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r' &&
           line[i] != '#')
      ++i;
    words.push_back(line.substr(start, i - start));
  }
  return words;
}

bool to_number(std::string_view word, double& out) {
  const char* first = word.data();
  if (!word.empty() && word.front() == '+') ++first;
  auto [ptr, ec] = std::from_chars(first, word.data() + word.size(), out);
  return !word.empty() && ec == std::errc() && ptr == word.data() + word.size() &&
         std::isfinite(out);
}

ConsoleParse error(std::string message) { return {EmptyLine{}, std::move(message)}; }

/// A word of the user's line quoted in an answer: one line (control characters as '?') and at
/// most kShownWord characters (a 100,000-character word is not echoed whole).
constexpr std::size_t kShownWord = 40;
std::string shown_word(std::string_view word) {
  std::string out;
  for (unsigned char c : word.substr(0, kShownWord))
    out += c < 0x20 || c == 0x7f ? '?' : static_cast<char>(c);
  if (word.size() > kShownWord) out += "... (" + std::to_string(word.size()) + " characters)";
  return out;
}

}  // namespace

ConsoleParse parse_console_line(std::string_view line) {
  const auto w = split_words(line);
  if (w.empty()) return {EmptyLine{}, {}};
  const std::string_view verb = w[0];
  const auto arity = [&](std::size_t n) { return w.size() == n + 1; };
  const auto usage = [&](std::string_view u) { return error("usage: " + std::string(u)); };

  if (verb == "idle" || verb == "rest" || verb == "hit" || verb == "auto" || verb == "reset" ||
      verb == "status" || verb == "help" || verb == "quit" || verb == "exit") {
    if (!arity(0)) return error(std::string(verb) + " takes no arguments");
    if (verb == "idle") return {IdleCmd{}, {}};
    if (verb == "rest") return {RestCmd{}, {}};
    if (verb == "hit") return {HitCmd{}, {}};
    if (verb == "auto") return {AutoCmd{}, {}};
    if (verb == "reset") return {ResetCmd{}, {}};
    if (verb == "status") return {StatusCmd{}, {}};
    if (verb == "help") return {HelpCmd{}, {}};
    return {QuitCmd{}, {}};
  }
  if (verb == "angle" || verb == "speed" || verb == "wait") {
    double v = 0.0;
    if (!arity(1) || !to_number(w[1], v))
      return usage(verb == "angle" ? "angle RAD" : verb == "speed" ? "speed M/S" : "wait SECONDS");
    if (verb == "angle") return {AngleCmd{v}, {}};
    if (verb == "speed") return {SpeedCmd{v}, {}};
    if (v < 0.0 || v > 3600.0) return error("wait: expected 0..3600 seconds");
    return {WaitCmd{v}, {}};
  }
  if (verb == "hole") {
    double x = 0.0, y = 0.0;
    if (!arity(2) || !to_number(w[1], x) || !to_number(w[2], y)) return usage("hole X Y");
    return {HoleCmd{x, y}, {}};
  }
  if (verb == "load") {
    if (!arity(2) || (w[1] != "hitting" && w[1] != "params"))
      return usage("load hitting|params FILE");
    return {LoadCmd{w[1] == "hitting" ? LoadCmd::What::kHitting : LoadCmd::What::kParams,
                    std::string(w[2])},
            {}};
  }
  if (verb == "record") {
    if (arity(1) && w[1] == "off") return {RecordCmd{false, {}}, {}};
    if (arity(2) && w[1] == "on") return {RecordCmd{true, std::string(w[2])}, {}};
    return usage("record on FILE | record off");
  }
  return error("unknown command '" + shown_word(verb) + "' (type help)");
}

std::string_view console_help() {
  return "idle                  gravity compensation: the arm stays where it is left\n"
         "rest                  move to the rest pose, club face across the hitting direction\n"
         "hit                   hit with the current angle and speed (from the rest pose)\n"
         "angle RAD             set the hitting angle (counter-clockwise from +x)\n"
         "speed M/S             set the hitting speed\n"
         "auto                  take angle and speed from the loaded parameter model\n"
         "hole X Y              move the hole (metres)\n"
         "reset                 put the ball back on the tee\n"
         "load hitting|params FILE   load a hitting model or a parameter model\n"
         "record on FILE | record off   record the module's state to a CSV file\n"
         "wait SECONDS          let the world run\n"
         "status                print state, angle, speed, ball, hole\n"
         "help                  this list\n"
         "quit                  leave\n";
}

}  // namespace mg::control
