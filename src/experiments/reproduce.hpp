#pragma once
/// `minigolf reproduce`: the thesis's chapter 6 end to end on the full system — data sets (shipped
/// or collected by the teacher), training (GPR, GMR, joint GMR), validation MSE (tables 6.1-6.4),
/// the robot playing random test situations (table 6.5) with the oracle ceiling, learning curves,
/// figures — into one folder with report.md, raw CSVs, the resolved configuration, seed and
/// revision. Thesis values appear only in the report's "thesis" columns.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace mg::experiments {

struct ReproduceOptions {
  bool quick = false;  ///< fewer situations and seeds (under 10 min on 2 cores)
  std::filesystem::path out = "out/reproduce";
  int threads = 0;
  std::uint64_t seed = 1;
  bool collect = false;  ///< collect the data sets with the teacher instead of reading them
  std::filesystem::path
      datasets;  ///< folder of <field>.csv and <field>-validation.csv (default: shipped)
  std::vector<std::string> fields{"flat", "multiple-hills", "regular-hill", "arctan"};
  std::string config;  ///< module config YAML (empty: defaults)
  std::string revision = "unknown";
  bool plots = true;   ///< draw the figures (matplotlib)
  bool beyond = true;  ///< the "beyond the thesis" part: self-teaching, baselines, noise
  /// The real-robot rows (flat, multiple-hills): this plant stands in for the real WAM
  /// (default data/plants/real-wam.yaml); skipped with `real_robot` false.
  bool real_robot = true;
  std::string real_robot_plant;
  /// A plant for the whole run (`--plant`): every putt happens in it (empty: the robot's model).
  std::string plant;
  /// A belief file for the whole run (`--belief`): the chapter's fields and the rounds are
  /// planned, collected and played in it (empty: the robot believes its field files). The
  /// real-robot rows start from the survey: they measure what the robot learns of the plant.
  std::string belief;
  /// The round of minigolf (beyond the thesis, docs/round.md): every shipped course by the robot,
  /// the oracle planner and the greedy player over this many seeds (0: skipped; default: 20, 3
  /// with `quick`).
  int round_seeds = -1;
};

/// Runs everything; `log` gets one line per step (progress). Throws InputError/IoError naming a
/// missing or bad input (a data set, the thesis values, a field).
void reproduce(const ReproduceOptions& options, const std::function<void(const std::string&)>& log);

/// Validation points and training points of the thesis's arctan protocol: `n_validation` indices
/// drawn without replacement from the non-corner points of an nx x ny grid (x-major order), the
/// corners always in training. Returns the validation indices, sorted.
std::vector<int> arctan_validation_split(int nx, int ny, int n_validation, std::uint64_t seed);

}  // namespace mg::experiments
