#pragma once
/// The robot plays (thesis 6.3, table 6.5): random test situations of the field's region, the
/// learner's predictions hit on the full system; success ratio with its 95 % Wilson interval,
/// and the oracle ceiling (the fraction of the same situations where the teacher finds any
/// sinking putt).
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "belief/belief.hpp"
#include "field/situations.hpp"
#include "game/round.hpp"
#include "learning/learner.hpp"
#include "system/system.hpp"
#include "teacher/teacher.hpp"

namespace mg::experiments {

/// 95 % Wilson score interval of k successes in n trials ([0, 1] for n = 0).
std::array<double, 2> wilson_interval(int k, int n, double z = 1.959963984540054);

/// Hitting parameters for hole positions (the ball on the tee) from a learner model whose inputs
/// are among field::kSituationInputs (xi = hole - ball, hole_x, hole_y, ball_x, ball_y) and whose
/// outputs include `angle` and either `speed` or a fixed speed (Model::fixed). Throws InputError
/// naming the mismatch.
struct Prediction {
  double angle = 0.0, speed = 0.0;          ///< [rad], [m/s]
  double angle_std = 0.0, speed_std = 0.0;  ///< predictive std (0 for a fixed speed)
};
std::vector<Prediction> predict_hits(const learning::Model& model, const field::Field& field,
                                     const std::vector<std::array<double, 2>>& holes);
/// The same for situations (inputs also among ball_x, ball_y; xi = hole - ball).
std::vector<Prediction> predict_hits(const learning::Model& model, const field::Field& field,
                                     const std::vector<field::Situation>& situations);
/// Throws InputError unless the model can be played on a field (see predict_hits): a fixed
/// speed is a finite club speed > 0, inside `system`'s safe envelope when one is given.
void check_playable_model(const learning::Model& model, const std::string& source,
                          const system::System* system = nullptr);

/// A learned model as a round plays it (game::RoundOptions::models, `play --model`): its inputs
/// as the robot standing at the ball facing +x sees the hole. A model over xi (hole - tee) is
/// asked for xi = hole - ball, from anywhere (the round judges each hit in its model of the field
/// before playing it); a model over hole_x, hole_y only with the ball within 1 cm of `field`'s
/// tee (the tee it was trained from). Throws InputError as check_playable_model.
game::HitModel round_hit_model(std::shared_ptr<const learning::Model> model,
                               const field::Field& field);

/// How `evaluate --learn` learns while playing.
enum class LearnMode {
  kResidual,  ///< the model is a prior; a residual GP over it learns from the labels (adaptation)
  kAppend,    ///< the labels join the GPR model's own data (the thesis's suggestion; a baseline)
};

struct EvaluateOptions {
  int situations = 30;
  std::uint64_t seed = 1;
  int threads = 0;
  bool oracle = true;               ///< also run the teacher on every situation
  teacher::TeacherOptions teacher;  ///< for the oracle
  // --- Noise. Zero: the run is unchanged, bit for bit.
  /// Std [m] of the perceived hole's and the perceived ball's position error, per axis (as the
  /// network vision feed adds): the robot chooses its putt for the xi it perceives.
  double perception_noise = 0.0;
  /// Execution noise: joint-torque disturbance std as a fraction of the limits (launch study).
  double torque_noise = 0.0;
  std::uint64_t noise_seed = 1;  ///< situation i draws from derive_seed(noise_seed, i)
  /// evaluate_learning: how new labels change the model.
  LearnMode learn = LearnMode::kResidual;
  /// evaluate_learning: situation counts after which the model as it stands is also kept.
  std::vector<int> learn_checkpoints;
  /// evaluate_learning: the robot also revises its belief from every putt it plays
  /// (experiments::BeliefReviser) and plans each later putt in it; false: the system's belief
  /// throughout (`--no-revise`).
  bool revise = false;
  /// The system's belief with its uncertainty, the revision's prior; none: the system's belief
  /// with the survey's spread.
  std::optional<belief::Belief> belief_prior;
  void validate() const;  ///< InputError naming the field
};

struct SituationResult {
  std::array<double, 2> hole{0, 0};
  std::array<double, 2> ball{0, 0};  ///< where the ball lay (the tee unless a ball region)
  Prediction predicted;
  bool in_envelope = true;  ///< false: no stance reaches the hit (system::hit_reachable; a miss)
  bool sunk = false;
  sim::PuttOutcome outcome;
  bool oracle_found = false;  ///< the teacher found a sinking putt here
  int oracle_full_putts = 0, oracle_ball_putts = 0;
};

struct Evaluation {
  std::vector<SituationResult> rows;
  int sunk = 0;
  double success_ratio = 0.0;
  std::array<double, 2> ci95{0, 1};
  int oracle_found = 0;
  double oracle_ceiling = 0.0;  ///< NaN without the oracle
};

/// Chooses the putts for a list of (perceived) situations.
using Policy = std::function<std::vector<Prediction>(const std::vector<field::Situation>&)>;

/// Plays `options.situations` situations drawn from `region` with `seed`
/// (Situations::sample_situations: the same for every policy, so methods are compared on the same
/// situations), each with the putt `policy` chooses for the situation as perceived; a ball off the
/// tee is hit with the base beside it (system::stance_for, aim 0). Same bits for any thread count.
Evaluation evaluate_policy(const system::System& system, const Policy& policy,
                           const field::Situations& region, const EvaluateOptions& options,
                           const std::function<void(int, int)>& progress = {});

/// evaluate_policy with a learner model's predictions (predict_hits).
Evaluation evaluate_model(const system::System& system, const learning::Model& model,
                          const field::Situations& region, const EvaluateOptions& options,
                          const std::function<void(int, int)>& progress = {});

/// Learning while playing (thesis chapter 7; adaptation, docs/reality.md): the situations are
/// played one after another and each putt's hindsight labels (selfteach/hindsight.hpp; the
/// arrival speed of the region's strategy) change the model before the next one:
///   kResidual  the model is the prior of a selfteach::Planner: a residual GP on (label - prior),
///              pseudo-labels for putts that label nothing near their target; `learned` is the
///              residual model over `model` (any method);
///   kAppend    the labels join a GPR model's data (hyperparameters re-tuned by marginal
///              likelihood whenever the data has grown by a third); GPR models only.
/// One thread: each putt depends on the ones before; deterministic.
struct LearningEvaluation {
  Evaluation evaluation;          ///< rows in play order
  std::vector<int> labels_added;  ///< per situation
  learning::Model learned;
  std::vector<std::pair<int, learning::Model>> checkpoint_models;  ///< (situations played, model)
  /// The belief each checkpoint model (and, last, `learned`) is to be played in.
  std::vector<plant::Plant> checkpoint_beliefs;
  belief::Belief belief;        ///< the belief at the end, with its std when it was revised
  int revisions = 0;            ///< times the belief was revised (EvaluateOptions::revise)
  double revision_max_cpu = 0;  ///< [s] the longest revision's CPU
};
LearningEvaluation evaluate_learning(const system::System& system, const learning::Model& model,
                                     const field::Situations& region,
                                     const EvaluateOptions& options,
                                     const std::function<void(int, int)>& progress = {});

/// CSV, one row per situation: hole_x,hole_y,xi_x,xi_y,angle,speed,angle_std,speed_std,
/// in_envelope,sunk,closest_approach,rest_x,rest_y,oracle_found,oracle_full_putts,oracle_ball_putts
/// (xi = hole - ball), and ball_x,ball_y when a ball lay off the tee.
std::string evaluation_csv(const Evaluation& e, const field::Field& field);

}  // namespace mg::experiments
