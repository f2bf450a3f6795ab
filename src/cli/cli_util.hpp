#pragma once
/// Small parsing helpers shared by the subcommands.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

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

/// Parses "a,b,c" into names (no empty entries); throws `InputError` naming `what`.
std::vector<std::string> parse_names(const std::string& what, const std::string& text);

using mg::run_plot_script;  ///< core/plot.hpp

/// The plant of `--plant PATH` (empty path: none, the identity). Throws InputError/IoError.
plant::Plant load_plant_arg(const std::string& path);
/// `plant` as reported in --json: null without a file, else {"path", "hash"}.
nlohmann::json plant_json(const plant::Plant& plant);
/// The help text of --plant.
inline constexpr const char* kPlantHelp =
    "Plant file: the world as it really is where it differs from the robot's model "
    "(docs/reality.md)";

/// The options every putting command shares (--field, --config, --hitting-model, --plant,
/// --threads).
struct SystemArgs {
  std::string field = "flat";
  std::string config;
  std::string hitting_model;
  std::string plant;
  int threads = 0;
};

inline void add_system_options(CLI::App* cmd, SystemArgs& a) {
  cmd->add_option("--field", a.field, "Shipped field name or path to a field file")
      ->capture_default_str();
  cmd->add_option("--config", a.config, "Module config YAML");
  cmd->add_option("--hitting-model", a.hitting_model,
                  "Hitting DS model file (default: the shipped one)");
  cmd->add_option("--plant", a.plant, kPlantHelp);
  cmd->add_option("--threads", a.threads, "Threads (0: all cores; results do not depend on it)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
}

}  // namespace mg::cli
