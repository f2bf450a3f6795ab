#pragma once
/// The robot teaches itself (beyond thesis chapter 7; docs/selfteach.md): no teacher, no data set.
/// It chooses its own putts on the full system, learns from every outcome, misses included, and
/// stops after a budget of full-system putts.
///
/// Each round:
/// 1. Target: among candidate hole positions of the region (its centre, its collection points,
///    random draws), the one where the current model is least sure (largest predictive std of the
///    residual GP below, in units of the sinking window: 0.004 rad, 0.03 m/s), halved for every
///    earlier target within 1 cm (a target the putts cannot reach is not tried for ever).
/// 2. Putt: prior + residual. The prior is what a person would use: aim at the hole, the launch
///    speed that rolls the distance (belief::prior_launch), mapped to the club by the launch
///    relation the robot measures on its own putts (median launch angle - theta and launch speed /
///    club speed; before the first putt 0 and 1.6, an elastic impact with restitution 0.6). A GP
///    per output on (label - prior) at the labels corrects it. A putt without a label near its
///    own target (it went too fast past the hole, whose cup spoils the path beyond) still tells
///    how it missed: its putt corrected by the miss (aim by lateral / distance, club speed by the
///    arrival energy, as the teacher's first Newton step) is a planning-only pseudo-label there,
///    dropped once a real label lies within 2 cm. The model written uses real labels only.
/// 3. Learn: the putt's ball path gives hindsight labels (selfteach/hindsight.hpp), whatever its
///    outcome. A putt whose label lies within 1 cm of its own target checks the labels for free:
///    it should have sunk. When such checks fail (two or more, and under 90 % sink), the arrival
///    speed s* is lowered by 15 % and every path is labelled again.
/// The model written is a plain GPR learner model (learning::Model, the region's inputs, a fixed
/// speed for angle-only regions) trained on the labels, so `evaluate`, `predict` and the console
/// play it unchanged. Deterministic: the same system, region and options give the same bits for
/// any thread count (the `batch` putts of a round are chosen before any is played).
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "field/situations.hpp"
#include "learning/learner.hpp"
#include "selfteach/hindsight.hpp"
#include "system/system.hpp"

namespace mg::selfteach {

struct SelfTeachOptions {
  int budget = 100;  ///< full-system putts, misses included (1..100000)
  std::uint64_t seed = 1;
  int batch = 1;         ///< putts chosen together per round (1..64), played in parallel
  int threads = 0;       ///< 0: all cores
  int candidates = 300;  ///< random candidate targets (plus centre and collection points)
  /// [m/s] the arrival speed s* to learn (angle-and-speed regions); 0: the region's strategy's
  /// (teacher::arrival_speed). robust_arrival_speed chooses one for a measured noise.
  double arrival_speed = 0.0;
  double record_interval = 0.005;  ///< [s] ball path sampling
  /// Putt counts after which the model is also trained and kept (learning curves); the model
  /// after k putts is the model a budget of k would give.
  std::vector<int> checkpoints;
  /// A model learned elsewhere to start from (`self-teach --prior`): the planner's prior is its
  /// prediction instead of the physical one, and the model written is a residual over it
  /// (selfteach/planner.hpp). nullptr: from scratch.
  std::shared_ptr<const learning::Model> prior;
  /// The robot revises its belief from its putts (experiments::BeliefReviser): called after each
  /// round with each putt in order (its situation, angle [rad, world], club speed [m/s] and
  /// result, trajectory recorded); returns the system in the revised belief, or nullptr to keep
  /// the current one. On a revision the planner and every hindsight label are rebuilt in the new
  /// belief. Empty: the belief is never revised.
  std::function<const system::System*(const field::Situation&, double, double,
                                      const control::FullPuttResult&)>
      revise;
  void validate() const;  ///< InputError naming the field
};

/// One of the robot's own putts.
struct PuttRecord {
  std::array<double, 2> target{0, 0};  ///< [m] where the hole was
  std::array<double, 2> ball{0, 0};    ///< [m] where the ball lay
  double angle = 0.0, speed = 0.0;     ///< [rad], [m/s] what it hit
  bool hit = false, sunk = false;
  double closest_approach = 0.0;                  ///< [m]
  double launch_angle = 0.0, launch_speed = 0.0;  ///< measured ball launch
  /// How the ball met the hole (sim::PuttOutcome): speed [m/s], lateral offset and how far short
  /// [m].
  double approach_speed = 0.0, approach_lateral = 0.0, approach_along = 0.0;
  int labels = 0;                ///< hindsight labels it gave (at the final s*)
  double label_distance = -1.0;  ///< [m] of its (first) label to its target; -1: none
};

struct SelfTeachResult {
  /// False: fewer than two labels in the budget (the region is out of the robot's reach: the
  /// field is unplayable for it); `model` is then empty.
  bool trained = false;
  learning::Model model;                            ///< trained on `labels`
  std::vector<Label> labels;                        ///< at the final s*
  std::vector<PuttRecord> putts;                    ///< in order
  std::vector<std::vector<sim::BallSample>> paths;  ///< each putt's ball path from the launch
  std::vector<std::pair<int, learning::Model>> checkpoint_models;  ///< (putts, model)
  /// The belief each checkpoint model is to be played in (the system's belief then; a model over
  /// an angle-only region reads its fixed speed in it), in the same order.
  std::vector<plant::Plant> checkpoint_beliefs;
  plant::Plant belief;          ///< the belief `model` is to be played in (the last system's)
  double arrival_speed = 0.0;   ///< final s* [m/s] (angle and speed regions)
  int arrival_corrections = 0;  ///< times s* was lowered
  int on_target = 0, on_target_sunk = 0;  ///< putts labelled within 1 cm of their own target
  int sunk = 0;                           ///< putts that sank while teaching
};

/// Learns `region` of `system`'s field (see the file comment). `progress(done, budget)` after each
/// round. Throws InputError for bad options.
SelfTeachResult self_teach(const system::System& system, const field::Situations& region,
                           const SelfTeachOptions& options,
                           const std::function<void(int, int)>& progress = {});

/// The learner model of `labels` (those of putts < `putts`; all for a negative value): GPR on the
/// region's inputs, fixed speed for angle-only regions. Throws InputError below two labels.
learning::Model model_from_labels(const system::System& system, const field::Situations& region,
                                  const std::vector<Label>& labels, int putts, std::uint64_t seed);

/// The prior's club (angle [rad], speed [m/s]) for `hole`: aim at it, the launch speed that
/// rolls there arriving at `arrival` [m/s] (belief::prior_launch; with an obstacle on the line,
/// the shortest bank shot, teacher::bank_shots), mapped through the launch
/// relation (launch angle - theta = `bias` [rad], launch speed / club speed = `ratio`); the
/// region's fixed speed for angle-only regions.
std::array<double, 2> prior_club(const field::Field& field, const field::Situations& region,
                                 const field::Situation& situation, double arrival, double bias,
                                 double ratio);
/// The record of a putt (angle, speed) from `situation`'s ball at its hole (the target) with
/// result `r` (labels not yet counted).
PuttRecord record_putt(const field::Situation& situation, double angle, double speed,
                       const control::FullPuttResult& r);
/// The launch relation (bias, ratio) measured on `putts` (medians; 0 and 1.6 before any).
std::array<double, 2> launch_relation(const std::vector<PuttRecord>& putts);

/// Plays the putt of `label` from its ball with the hole really at its position: did it sink?
/// (The check of a hindsight label.)
bool replay_label(const system::System& system, system::SystemData& data, const Label& label);

}  // namespace mg::selfteach
