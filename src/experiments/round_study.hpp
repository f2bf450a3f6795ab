#pragma once
/// Beyond the thesis: a round of minigolf (docs/round.md). Every shipped course (or the given
/// ones) played by the robot, the oracle planner and the greedy player over seeds; the report's
/// tables, a CSV of every stroke and a PNG of each hole's ball paths over the field.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "game/report.hpp"

namespace mg::experiments {

struct RoundStudyOptions {
  std::vector<std::string> courses;  ///< empty: every shipped course
  int seeds = 20;
  std::uint64_t seed = 1;
  int threads = 0;
  int budget = game::RoundOptions{}.calibration_putts;  ///< learning putts per field
  std::string config;                                   ///< module config YAML (empty: defaults)
  std::string plant;   ///< plant file (empty: the robot's model is the world)
  std::string belief;  ///< belief file: the robot plans in it (empty: its field files)
  bool plots = true;   ///< one PNG per hole (the robot's rounds)
};

struct RoundStudy {
  std::vector<game::CourseRounds> rounds;  ///< per course
  std::string markdown;                    ///< the tables and the figure links
};

/// The robot's learned models of a round from FIELD=FILE specs (FIELD: a shipped name or a field
/// file; FILE: a model of `minigolf train`), keyed by field name (round_hit_model). Throws
/// InputError naming `what` and the spec.
std::map<std::string, game::HitModel> load_round_models(const std::vector<std::string>& specs,
                                                        const std::string& what);

/// Plays and reports into `out` (rounds.csv, rounds.md, figures/round-<course>-hole<K>.png).
/// `log` gets progress lines.
RoundStudy round_study(const RoundStudyOptions& options, const std::filesystem::path& out,
                       const std::function<void(const std::string&)>& log);

}  // namespace mg::experiments
