#pragma once
/// Small parsing helpers shared by the subcommands.
#include <array>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "core/plot.hpp"
#include "plant/plant.hpp"

namespace mg::cli {

/// The one policy for numbers on the command line: typed CLI11 options with these validators.
/// A rejected value is a CLI::ValidationError, which `main` reports in one line with exit 2.
///
/// A finite number in [lo, hi] (CLI::Range lets NaN through; CLI11 itself parses "nan", "inf").
CLI::Validator finite_number(double lo, double hi);
/// Any finite number.
CLI::Validator finite_number();
/// Any text (the element check of a list of names).
CLI::Validator any_name();

/// The elements of a comma-separated list, empty ones kept ("a,,b" -> "a", "", "b"; "" -> "").
std::vector<std::string> split_list(const std::string& text);
/// A comma-separated list whose every element passes `element`; an empty element ("1,,2", "1,")
/// is an error (CLI11's own delimiter would skip it: an ignored argument).
CLI::Validator list_of(const CLI::Validator& element);

/// The one way to take a list on the command line: `--name a,b,c` (one token per occurrence)
/// into `target` (double, int or std::string elements), every element checked by `element`
/// (list_of). A rejected list is a CLI::ValidationError naming the option: one line, exit 2.
/// The default shown in --help is `target`'s value.
template <typename T>
CLI::Option* add_list_option(CLI::App* cmd, const std::string& name, std::vector<T>& target,
                             const std::string& help, const CLI::Validator& element) {
  CLI::Option* opt = cmd->add_option_function<std::string>(
      name,
      [&target](const std::string& text) {
        std::vector<T> out;
        for (const std::string& item : split_list(text)) {
          if constexpr (std::is_same_v<T, std::string>) {
            out.push_back(item);
          } else {  // checked by list_of(element) before this runs
            T v{};
            std::from_chars(item.data() + (item.front() == '+' ? 1 : 0), item.data() + item.size(),
                            v);
            out.push_back(v);
          }
        }
        target = std::move(out);
      },
      help);
  opt->check(list_of(element));
  opt->type_name("LIST");
  opt->default_str(fmt::format("{}", fmt::join(target, ",")));
  return opt;
}
/// An output file: its target is checked when the command line is read, before any work
/// (mg::check_output_file: the folder exists and is writable; the target is absent or a regular
/// file, never a FIFO, link, device or folder). Every file-writing option carries it.
CLI::Validator output_file();

/// The one rule for empty values: every option and positional argument of `app` and its
/// subcommands that takes a value refuses an empty one (`--angle ''`, `-o ''`) with a
/// CLI::ValidationError naming it; an empty value would otherwise read as "not given" (a
/// default, nothing written). Call once, after every subcommand is added.
void refuse_empty_values(CLI::App& app);

/// `text` as one line of at most `max` characters: control characters (a newline would split
/// the line) shown as '?', a longer text shortened in the middle ("... (N characters) ...").
std::string one_line(std::string_view text, std::size_t max = 1000);

/// Putt counts on the command line at most (checkpoints of the learning curves).
inline constexpr std::uint64_t kMaxCheckpoint = 1000000;
/// A decimal integer in [0, hi]: no sign, no fraction, no exponent (CLI11's own conversion turns
/// "-1" into 2^64 - 1).
CLI::Validator unsigned_integer(std::uint64_t hi = UINT64_MAX);

/// Parses the whole of `text` (an optional leading '+') as a finite double; throws `InputError`
/// naming `what` ("expected a number" / "expected a finite number").
double parse_number(const std::string& what, const std::string& text);

/// Parses the whole of `text` as a non-negative integer; throws `InputError` naming `what`.
std::uint64_t parse_unsigned(const std::string& what, const std::string& text);

/// Parses "a,b" (or "a,b,c" with N = 3) into finite doubles; throws `InputError` naming `what`.
template <std::size_t N>
std::array<double, N> parse_vector(const std::string& what, const std::string& text);

using mg::run_plot_script;  ///< core/plot.hpp

/// The plant of `--plant PATH` (empty path: none, the identity). Throws InputError/IoError.
plant::Plant load_plant_arg(const std::string& path);
/// `plant` as reported in --json: null without a file, else {"path", "hash"}.
nlohmann::json plant_json(const plant::Plant& plant);
/// The help text of --plant.
inline constexpr const char* kPlantHelp =
    "Plant file: the world as it really is where it differs from the robot's model "
    "(docs/reality.md)";

/// The robot's belief of `--belief PATH` (docs/belief.md; empty path: none, it believes its
/// field file), as the plant keys it estimates. Throws InputError/IoError.
plant::Plant load_belief_arg(const std::string& path);
inline constexpr const char* kBeliefHelp =
    "Belief file: what the robot believes of the world beyond its field file, e.g. from "
    "`minigolf identify` (docs/belief.md)";

/// The options every putting command shares (--field, --config, --hitting-model, --plant,
/// --belief, --threads).
struct SystemArgs {
  std::string field = "flat";
  std::string config;
  std::string hitting_model;
  std::string plant;
  std::string belief;
  int threads = 0;
};

inline void add_system_options(CLI::App* cmd, SystemArgs& a) {
  cmd->add_option("--field", a.field, "Shipped field name or path to a field file")
      ->capture_default_str();
  cmd->add_option("--config", a.config, "Module config YAML");
  cmd->add_option("--hitting-model", a.hitting_model,
                  "Hitting DS model file (default: the shipped one)");
  cmd->add_option("--plant", a.plant, kPlantHelp);
  cmd->add_option("--belief", a.belief, kBeliefHelp);
  cmd->add_option("--threads", a.threads, "Threads (0: all cores; results do not depend on it)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
}

/// The folder `dir` for --frames, made when missing. Throws InputError naming it.
std::filesystem::path frames_dir(const std::string& dir);

}  // namespace mg::cli
