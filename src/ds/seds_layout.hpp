#pragma once
/// The SEDS parameter vector's layout (seds.cpp packs, unpacks and differentiates it; seds_fit.cpp
/// bounds and constrains it): K blocks, one per Gaussian, each block_size(objective) numbers.
#include <cmath>

#include <Eigen/Core>

#include "ds/seds.hpp"

namespace mg::ds::seds_layout {

/// Parameters of a 3 x 3 covariance: its Cholesky factor's lower triangle (log diagonal).
inline constexpr int kCholeskySize = 6;
/// One Gaussian's block: log prior, mu (3), the Cholesky parameters of Sigma (6), A (9,
/// column-major), and with the likelihood objective those of C (6).
inline constexpr int kLogPrior = 0;
inline constexpr int kMu = 1;
inline constexpr int kSigma = kMu + 3;
inline constexpr int kA = kSigma + kCholeskySize;
inline constexpr int kC = kA + 9;

/// Numbers per Gaussian.
inline int block_size(SedsObjective objective) {
  return kC + (objective == SedsObjective::kLikelihood ? kCholeskySize : 0);
}

/// log(sum(exp(v))) without overflow (-inf or NaN as the largest element when not finite).
inline double log_sum_exp(const Eigen::VectorXd& v) {
  const double m = v.maxCoeff();
  if (!std::isfinite(m)) return m;
  return m + std::log((v.array() - m).exp().sum());
}

}  // namespace mg::ds::seds_layout
