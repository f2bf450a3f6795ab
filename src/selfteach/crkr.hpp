#pragma once
/// Cost-regularized Kernel Regression (Kober, Wilhelm, Oztop, Peters 2012), the reinforcement-
/// learning route the thesis names as future work: a baseline for the self-teacher, with the same
/// physics prior, the same full-system putts and the same accounting.
///
/// Policy over the situation s (the region's inputs) for the action a = (theta[, v]) as a
/// residual from the prior (selfteach::prior_club with the measured launch relation):
///   mean(s) = k(s)^T (K + lambda C)^-1 A,   var(s) = k(s, s) + lambda - k(s)^T (K + lambda C)^-1
///   k(s)
/// with a Gaussian kernel on s, C = diag(costs) of the rollouts so far and A their residual
/// actions. Each episode draws a situation from the region, explores with
/// a ~ N(prior + mean(s), var(s) diag(sigma^2)), putts on the full system and records the cost
///   c = 0.02 when it sank, else 0.02 + closest approach / 0.05 m (+ |arrival - s*| / 0.5 m/s).
/// The learned policy is the mean.
#include <array>
#include <cstdint>
#include <vector>

#include "field/situations.hpp"
#include "selfteach/self_teach.hpp"
#include "system/system.hpp"

namespace mg::selfteach {

struct CrkrOptions {
  int budget = 100;  ///< episodes = full-system putts (1..100000)
  std::uint64_t seed = 1;
  double lambda = 0.5;        ///< cost regularisation
  double bandwidth = 0.0;     ///< [m] kernel width; 0: a quarter of the region's extent (>= 2 cm)
  double sigma_angle = 0.01;  ///< [rad] exploration scale
  double sigma_speed = 0.05;  ///< [m/s]
  std::vector<int> checkpoints;  ///< episode counts after which the policy is kept
  void validate() const;
};

/// A CrKR policy: the rollouts it regresses on.
struct CrkrPolicy {
  std::vector<std::array<double, 2>> holes;      ///< [m]
  std::vector<std::array<double, 2>> residuals;  ///< (angle, speed) - prior at the hole
  std::vector<double> costs;
  double lambda = 0.5, bandwidth = 0.1;
  double arrival = 0.4, bias = 0.0, ratio = 1.6;  ///< the prior's parameters
  /// Mean action (angle, speed) and the std factor sqrt(var) at `hole`.
  std::array<double, 3> act(const field::Field& field, const field::Situations& region,
                            std::array<double, 2> hole) const;
};

struct CrkrResult {
  CrkrPolicy policy;
  std::vector<PuttRecord> putts;
  std::vector<std::pair<int, CrkrPolicy>> checkpoint_policies;
  int sunk = 0;
};

CrkrResult crkr_learn(const system::System& system, const field::Situations& region,
                      const CrkrOptions& options);

}  // namespace mg::selfteach
