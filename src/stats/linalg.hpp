#pragma once
/// Small numerical helpers shared by the GMM, GMR and GPR code.
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "core/error.hpp"

namespace mg::stats {

/// log(sum exp(v_i)) without overflow or underflow; -inf if every entry is -inf (or v is empty).
template <typename Derived>
double log_sum_exp(const Eigen::DenseBase<Derived>& v) {
  if (v.size() == 0) return -std::numeric_limits<double>::infinity();
  const double m = v.maxCoeff();
  if (!std::isfinite(m)) return m;
  return m + std::log((v.derived().array() - m).exp().sum());
}

/// Lower Cholesky factor of a symmetric matrix; if it is not numerically positive definite, adds
/// a growing jitter (1e-12 .. 1e-2 times the mean diagonal) until it is. Throws
/// `mg::NumericalError` if even that fails (e.g. NaN entries).
inline Eigen::MatrixXd robust_cholesky(const Eigen::MatrixXd& a, double* jitter_used = nullptr) {
  Eigen::LLT<Eigen::MatrixXd> llt(a);
  if (llt.info() == Eigen::Success) {
    if (jitter_used) *jitter_used = 0.0;
    return llt.matrixL();
  }
  const double scale = std::max(a.diagonal().cwiseAbs().mean(), std::numeric_limits<double>::min());
  for (double j = 1e-12; j <= 1e-2; j *= 10.0) {
    Eigen::MatrixXd b = a;
    b.diagonal().array() += j * scale;
    llt.compute(b);
    if (llt.info() == Eigen::Success) {
      if (jitter_used) *jitter_used = j * scale;
      return llt.matrixL();
    }
  }
  throw NumericalError(
      fmt::format("Cholesky: expected a positive definite {} x {} matrix, even with jitter",
                  a.rows(), a.cols()));
}

}  // namespace mg::stats
