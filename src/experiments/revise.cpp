#include "experiments/revise.hpp"

#include <algorithm>
#include <ctime>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "system/observe.hpp"

namespace mg::experiments {
namespace {

/// [s] The perceived path's sampling: the identification putts' (a learning putt records finer).
constexpr double kPathInterval = 0.01;

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace

BeliefReviser::BeliefReviser(const system::System& start, std::optional<belief::Belief> prior,
                             std::uint64_t seed)
    : start_(start), prior_(std::move(prior)), seed_(seed) {
  if (prior_)
    belief_ = *prior_;
  else
    belief_.estimate = start.belief();
}

bool BeliefReviser::observe(const field::Situation& situation, double angle, double speed,
                            const control::FullPuttResult& result) {
  if (!result.hit) return false;
  const double t0 = cpu_seconds();
  IdentifyHit h;
  h.situation = situation;
  h.angle = angle;
  h.speed = speed;
  h.path.hole = situation.hole;
  // The world's vision error on what the robot sees (the plant generates the measurement; the
  // fit never reads it). A path its own cameras saw (system::perceive_putt) has theirs already.
  const double noise =
      system::paths_seen_by_perception(start_) ? 0.0 : start_.plant().perception.noise;
  perceive_hit(h, result, noise, derive_seed(seed_, static_cast<std::uint64_t>(hits_.size())),
               kPathInterval);
  hits_.push_back(std::move(h));
  std::optional<belief::Belief> prior = prior_;
  if (!prior && !start_.belief().empty()) prior = belief::Belief{start_.belief()};
  Identification id;
  try {
    // Every run of a path: a learning putt crosses the lane's crests at speed.
    id = identify_belief(start_.config(), start_.survey(), hits_, hits_.size(), prior, true);
  } catch (const NumericalError&) {
    return false;  // nothing rolled long enough to fit yet
  }
  belief_ = std::move(id.belief);
  previous_ = std::move(current_);
  current_ = system_in_belief(start_, belief_.estimate);
  ++revisions_;
  last_cpu_ = cpu_seconds() - t0;
  max_cpu_ = std::max(max_cpu_, last_cpu_);
  return true;
}

std::unique_ptr<system::System> system_in_belief(const system::System& base,
                                                 const plant::Plant& belief) {
  return std::make_unique<system::System>(base.config(), base.survey(), base.plant(), belief,
                                          base.perception_factory());
}

std::unique_ptr<BeliefReviser> revise_hook(const system::System& system,
                                           selfteach::SelfTeachOptions& options,
                                           std::optional<belief::Belief> prior) {
  auto reviser =
      std::make_unique<BeliefReviser>(system, std::move(prior), derive_seed(options.seed, 71));
  options.revise = [r = reviser.get()](const field::Situation& s, double angle, double speed,
                                       const control::FullPuttResult& result) {
    return r->observe(s, angle, speed, result) ? &r->system() : nullptr;
  };
  return reviser;
}

}  // namespace mg::experiments
