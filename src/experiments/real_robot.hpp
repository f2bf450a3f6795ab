#pragma once
/// The "real-robot rows" of `minigolf reproduce` (thesis table 6.5's real-robot rows):
/// on the thesis's real-robot fields a documented plant (data/plants/real-wam.yaml) stands in for
/// the real WAM. Rows: the nominal-simulator model on 10 test situations there; the same model
/// after 10 of the robot's own putts, once as a residual over it in the survey's world
/// (self-teach --prior, the belief never revised) and once with the belief revised from the first
/// 3 (identify) and the residual from the other 7, played in that belief; beside the plant's
/// oracle ceiling. Then the adaptation curves over random plants (experiments/adaptation.hpp).
#include <functional>
#include <map>
#include <string>

#include "control/module_config.hpp"
#include "field/situations.hpp"
#include "learning/learner.hpp"
#include "plant/plant.hpp"

namespace mg::experiments {

struct RealRobotOptions {
  bool quick = false;
  int threads = 0;
  std::uint64_t seed = 1;
  plant::Plant plant;  ///< the stand-in for the real arm and lane
  int attempts = 10;   ///< the thesis's real-robot attempt count
  int adaptation_putts = 10;
  /// Of the adaptation putts, those the revised rows spend identifying the belief first.
  int identify_putts = 3;
  /// The thesis's real-robot success ratio of (field, method), NaN if none.
  std::function<double(const std::string&, const std::string&)> thesis;
  std::function<std::string(const std::string&)> csv_path;
  std::function<std::string(const std::string&)> fig_path;
  std::function<void(const std::string&, const std::string&)> plot;  ///< plot.py arguments, PNG
  std::function<void(const std::string&)> say;
};

/// Markdown rows by table: "rows" (the table 6.5-like rows), "curves" (adaptation curves) and
/// "figures". `models`: the nominal teacher-trained learners by method (gpr, gmr used).
std::map<std::string, std::string> real_robot_rows(
    const control::ModuleConfig& config, const std::string& name, const field::Situations& region,
    const std::map<std::string, learning::Model>& models, const RealRobotOptions& options);

}  // namespace mg::experiments
