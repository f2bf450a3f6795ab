#pragma once
/// The robot revises what it believes while it learns (docs/belief.md, "Revising while
/// learning"): every putt it plays, a learning putt or a test, is also an identification putt.
/// Its perceived ball path and the club speed its joints reached join the earlier ones, the
/// belief is fitted again from all of them (identify_belief, with the belief it started from as
/// the prior), and the robot plans from then on in a system built on the revised belief. The truth
/// (the plant) only builds the worlds the putts happen in, as everywhere.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "belief/belief.hpp"
#include "experiments/identify.hpp"
#include "selfteach/self_teach.hpp"
#include "sim_backend/full_system.hpp"
#include "system/system.hpp"

namespace mg::experiments {

class BeliefReviser {
 public:
  /// Starts from `start` (its belief is where the robot starts; `prior`, when given, is that
  /// belief with its uncertainty, the fit's prior). `seed` seeds the vision's error.
  BeliefReviser(const system::System& start, std::optional<belief::Belief> prior,
                std::uint64_t seed);
  BeliefReviser(const BeliefReviser&) = delete;
  BeliefReviser& operator=(const BeliefReviser&) = delete;

  /// The system to plan in: the start's until the first revision, then the revised belief's.
  const system::System& system() const { return current_ != nullptr ? *current_ : start_; }
  /// The belief now (the prior, or an empty belief, before the first revision).
  const belief::Belief& belief() const { return belief_; }
  int revisions() const { return revisions_; }
  /// [s] CPU of the last and of the longest revision (fits, predictions, the new system).
  double last_cpu() const { return last_cpu_; }
  double max_cpu() const { return max_cpu_; }

  /// Watches a putt of the ball `situation.ball` (hole seen at `situation.hole`) hit towards
  /// `angle` [rad, world] at club speed `speed` [m/s] with `result` (its trajectory recorded),
  /// and revises the belief from every putt watched so far. Returns true when it was revised; a
  /// putt that did not strike the ball, or paths that do not roll long enough to fit, change
  /// nothing.
  bool observe(const field::Situation& situation, double angle, double speed,
               const control::FullPuttResult& result);

 private:
  const system::System& start_;
  std::optional<belief::Belief> prior_;
  std::uint64_t seed_;
  std::vector<IdentifyHit> hits_;
  belief::Belief belief_;
  std::unique_ptr<system::System> current_;
  /// The system before the last revision, alive until the next one: the caller's data of it
  /// (its mjData, its cameras) is replaced after `observe` returns, not before.
  std::unique_ptr<system::System> previous_;
  int revisions_ = 0;
  double last_cpu_ = 0.0, max_cpu_ = 0.0;
};

/// The system of `base`'s configuration, field file, world (its plant) and perception (its
/// cameras, if any) with the robot's belief `belief` instead of base's.
std::unique_ptr<system::System> system_in_belief(const system::System& base,
                                                 const plant::Plant& belief);

/// A reviser starting from `system` (no prior beyond its belief; vision seeded by options.seed),
/// hooked into `options.revise` (self-teach revises through it). Keep it alive while
/// self_teach runs.
std::unique_ptr<BeliefReviser> revise_hook(const system::System& system,
                                           selfteach::SelfTeachOptions& options,
                                           std::optional<belief::Belief> prior = std::nullopt);

}  // namespace mg::experiments
