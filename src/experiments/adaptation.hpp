#pragma once
/// The adaptation study (docs/reality.md): a model learned in the nominal simulator,
/// played on seeded random plants (plant::random_plant) of a field, before and after a few of the
/// robot's own putts there. Per plant: what the nominal model sinks, the plant's oracle ceiling
/// (the teacher under the plant, allowed to see the truth), and what the adapted model sinks after
/// each checkpoint of adaptation putts, all on the same `situations` test situations.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "experiments/learning_curves.hpp"
#include "field/field.hpp"
#include "learning/learner.hpp"
#include "plant/plant.hpp"

namespace mg::experiments {

struct AdaptationOptions {
  int plants = 10;  ///< plant k: plant::random_plant(plant_seed + k) (`plant random --seed`)
  std::uint64_t plant_seed = 1;
  std::vector<int> checkpoints{0, 1, 2, 3, 5, 10};  ///< adaptation putts (0: the nominal model)
  int situations = 100;                             ///< test situations per checkpoint
  std::uint64_t test_seed = 7;
  std::uint64_t seed = 1;                       ///< the adaptation runs
  CurveLearner learner = CurveLearner::kAdapt;  ///< adapt | adapt-play | append | self-teach
  bool oracle = true;                           ///< also the plant's oracle ceiling
  /// The robot also revises its belief from its adaptation putts (CurveOptions::revise).
  bool revise = true;
  int threads = 0;
  /// Plants given instead of random ones (a documented stand-in for the real WAM, say).
  std::vector<plant::Plant> given;
  void validate() const;
};

struct PlantAdaptation {
  int index = 0;
  plant::Plant plant;
  std::vector<int> putts;  ///< the checkpoints
  std::vector<int> sunk;   ///< test situations sunk after that many adaptation putts
  int situations = 0;
  int oracle_found = -1;  ///< -1 without the oracle
};

/// Runs the study on `config`'s field (the robot's belief) with `prior` as the nominal model.
/// Plants run in parallel (and over MPI processes); the same bits for any thread count.
std::vector<PlantAdaptation> adaptation_study(const control::ModuleConfig& config,
                                              std::shared_ptr<const learning::Model> prior,
                                              const field::Situations& region,
                                              const AdaptationOptions& options,
                                              const std::function<void(int, int)>& progress = {});

/// CSV: plant,learner,putts,sunk,situations,success,oracle_found,oracle_ceiling,of_ceiling.
std::string adaptation_csv(const std::vector<PlantAdaptation>& rows, CurveLearner learner);

/// Per checkpoint over plants: median, 10 % and 90 % quantiles and the worst of the success ratio
/// and of the ratio to the plant's oracle ceiling (NaN without the oracle).
struct AdaptationSummary {
  std::vector<int> putts;
  std::vector<double> median, q10, q90, worst;
  std::vector<double> of_ceiling_median, of_ceiling_worst;
  std::vector<int> plants_at_goal;  ///< plants at >= 95 % of their ceiling
};
AdaptationSummary summarize_adaptation(const std::vector<PlantAdaptation>& rows);

}  // namespace mg::experiments
