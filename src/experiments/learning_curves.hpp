#pragma once
/// Learning curves: success on the same random test situations against the
/// full-system putts a learner has spent, misses included, for
///   self-teach    the robot alone (selfteach::self_teach);
///   teacher-gpr   the thesis protocol: the teacher collects examples at random situations of the
///                 region, one after another, every full-system putt it spends counted (its
///                 ball-only proposals are not: the thesis does not count a person's thinking);
///                 GPR on the examples found so far;
///   crkr          Cost-regularized Kernel Regression (selfteach/crkr.hpp).
/// Adaptation from a prior model (CurveOptions::prior; docs/reality.md):
///   adapt         self-teaching from the prior (self-teach --prior): the robot chooses its
///   targets,
///                 a residual over the prior learns;
///   adapt-play    learning while playing random situations of the region (evaluate --learn), the
///                 residual way;
///   append        the same, the labels appended to the prior GPR's own data and refitted (the
///                 thesis's suggestion: "the model could be improved by adding new examples").
/// A checkpoint 0 plays the prior as it is (the learners that start from scratch: 0 sunk).
/// A run per seed; at each checkpoint the learner as it stood is played on `situations` test
/// situations (evaluate_policy, seed `test_seed`, no noise). Runs go in parallel (one per thread);
/// the same bits for any thread count.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "experiments/evaluate.hpp"
#include "field/situations.hpp"
#include "system/system.hpp"

namespace mg::experiments {

enum class CurveLearner { kSelfTeach, kTeacherGpr, kCrkr, kAdapt, kAdaptPlay, kAppend };
std::string to_string(
    CurveLearner l);  ///< "self-teach", "teacher-gpr", "crkr", "adapt", "adapt-play", "append"
/// Inverse of to_string; throws InputError listing the choices.
CurveLearner parse_curve_learner(const std::string& name);
/// True for the learners that start from CurveOptions::prior.
bool needs_prior(CurveLearner l);

struct CurveOptions {
  std::vector<int> checkpoints{10, 25, 50, 100, 150};  ///< putts spent
  int seeds = 10;                                      ///< runs (seed 1..seeds derived from `seed`)
  int situations = 100;                                ///< test situations per checkpoint
  std::uint64_t seed = 1;
  std::uint64_t test_seed = 7;
  int threads = 0;
  teacher::TeacherOptions
      teacher;  ///< teacher-gpr; adapt-play and append: the strategy's arrival speed
  std::shared_ptr<const learning::Model> prior;  ///< adapt, adapt-play, append
  /// adapt, adapt-play, append: the robot also revises its belief from its putts
  /// (experiments::BeliefReviser), and each checkpoint's model is tested in the belief it had
  /// then; false: never revised (`--no-revise`).
  bool revise = true;
  void validate() const;
};

struct CurveRun {
  CurveLearner learner = CurveLearner::kSelfTeach;
  int run = 0;             ///< 0..seeds-1
  std::vector<int> putts;  ///< the checkpoints
  std::vector<int> sunk;   ///< test situations sunk at each (0 without a model yet)
  int situations = 0;
  int examples = 0;  ///< teacher-gpr: examples found within the last checkpoint
};

std::vector<CurveRun> learning_curves(const system::System& system, const field::Situations& region,
                                      CurveLearner learner, const CurveOptions& options,
                                      const std::function<void(int, int)>& progress = {});

/// CSV: learner,run,putts,sunk,situations,success.
std::string curves_csv(const std::vector<CurveRun>& runs);

/// Median and 10 / 90 % quantiles of the success ratio over runs at each checkpoint (linear
/// interpolation between order statistics).
struct CurveSummary {
  std::vector<int> putts;
  std::vector<double> median, q10, q90;
};
CurveSummary summarize(const std::vector<CurveRun>& runs);

}  // namespace mg::experiments
