// Model selection of the GMM-based learners: column standardisation, the number of Gaussians
// (BIC or cross-validation) and the covariance regularisation (cross-validated against the
// default by rows), for train() in learner.cpp.
#include "learning/model_selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "stats/gmr.hpp"

namespace mg::learning::detail {

Standardizer make_standardizer(const Eigen::MatrixXd& m) {
  Standardizer s;
  s.mean = m.colwise().mean().transpose();
  s.scale.resize(m.cols());
  for (Eigen::Index j = 0; j < m.cols(); ++j) {
    const double sd = std::sqrt((m.col(j).array() - s.mean(j)).square().mean());
    // A column whose spread is rounding noise of its values is constant: dividing by that noise
    // would blow a query a few ulps away up to 1e13 standard deviations (and GMR's linear
    // extrapolation with it).
    const double magnitude = m.col(j).cwiseAbs().maxCoeff();
    const bool negligible = !(sd > kNegligibleSpread * magnitude) || !std::isfinite(sd);
    s.scale(j) = negligible ? 1.0 : sd;
  }
  return s;
}

Eigen::MatrixXd apply(const Standardizer& s, const Eigen::MatrixXd& m) {
  return (m.rowwise() - s.mean.transpose()).array().rowwise() / s.scale.transpose().array();
}

std::vector<int> iota_dims(int first, int count) {
  std::vector<int> v(static_cast<std::size_t>(count));
  std::iota(v.begin(), v.end(), first);
  return v;
}

namespace {

// Squared GMR error (standardised outputs, summed over outputs) of every row when it is held
// out, K components, by cross-validation.
Eigen::VectorXd cv_errors(const Eigen::MatrixXd& joint, int num_inputs, int k, int folds,
                          const std::vector<int>& fold_of, std::uint64_t seed,
                          const stats::EmOptions& em) {
  const Eigen::Index n = joint.rows();
  const int num_outputs = static_cast<int>(joint.cols()) - num_inputs;
  Eigen::VectorXd err = Eigen::VectorXd::Zero(n);
  for (int f = 0; f < folds; ++f) {
    std::vector<Eigen::Index> train_rows, test_rows;
    for (Eigen::Index i = 0; i < n; ++i)
      (fold_of[static_cast<std::size_t>(i)] == f ? test_rows : train_rows).push_back(i);
    if (test_rows.empty()) continue;
    if (static_cast<int>(train_rows.size()) < k)
      return Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
    Eigen::MatrixXd train(static_cast<Eigen::Index>(train_rows.size()), joint.cols());
    for (std::size_t i = 0; i < train_rows.size(); ++i)
      train.row(static_cast<Eigen::Index>(i)) = joint.row(train_rows[i]);
    mg::Rng rng(mg::derive_seed(seed, static_cast<std::uint64_t>(1000 * k + f)));
    const stats::Gmm g = stats::fit_gmm(train, k, rng, em).gmm;
    const stats::GmrConditioner cond(g, iota_dims(0, num_inputs),
                                     iota_dims(num_inputs, num_outputs));
    auto ws = cond.make_workspace();
    Eigen::VectorXd out(num_outputs);
    for (Eigen::Index r : test_rows) {
      cond.predict_mean(joint.row(r).head(num_inputs).transpose(), out, ws);
      err(r) = (out - joint.row(r).tail(num_outputs).transpose()).squaredNorm();
    }
  }
  return err;
}

// Seeded shuffle of n rows into `folds` folds.
std::vector<int> make_folds(int n, int folds, mg::Rng& rng) {
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  for (int i = n - 1; i > 0; --i)
    std::swap(order[static_cast<std::size_t>(i)], order[rng() % static_cast<std::uint64_t>(i + 1)]);
  std::vector<int> fold_of(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    fold_of[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])] = i % folds;
  return fold_of;
}

// cv_errors, or +inf everywhere if a fold's fit fails (a value of reg_covar too small for the
// data).
Eigen::VectorXd cv_errors_or_inf(const Eigen::MatrixXd& joint, int num_inputs, int k, int folds,
                                 const std::vector<int>& fold_of, std::uint64_t seed,
                                 const stats::EmOptions& em) {
  const auto failed = [&] {
    return Eigen::VectorXd::Constant(joint.rows(), std::numeric_limits<double>::infinity());
  };
  try {
    const Eigen::VectorXd e = cv_errors(joint, num_inputs, k, folds, fold_of, seed, em);
    return e.allFinite() ? e : failed();
  } catch (const Error&) {
    return failed();
  }
}

double mean_or_inf(const Eigen::VectorXd& e) {
  return e.allFinite() ? e.mean() : std::numeric_limits<double>::infinity();
}

// Whether `candidate`'s held-out errors are measurably below `baseline`'s: lower by at least
// min_gain of the baseline's mean, and the paired mean difference more than two standard
// errors below zero (rows are the pairs: the same folds hold the same rows out).
bool measurably_lower(const Eigen::VectorXd& candidate, const Eigen::VectorXd& baseline,
                      double min_gain) {
  if (candidate.size() == 0 || !candidate.allFinite()) return false;
  if (baseline.size() != candidate.size() || !baseline.allFinite())
    return true;  // the baseline failed
  const Eigen::Index n = candidate.size();
  if (n < 2) return false;
  const Eigen::VectorXd d = candidate - baseline;
  const double mean = d.mean();
  const double se = std::sqrt((d.array() - mean).square().sum() / static_cast<double>(n - 1) /
                              static_cast<double>(n));
  return mean < -min_gain * baseline.mean() && mean < -2.0 * se;
}

}  // namespace

GmmFit fit_gmm_model(const Eigen::MatrixXd& joint, int num_inputs, const TrainOptions& opt,
                     std::uint64_t seed) {
  const int n = static_cast<int>(joint.rows());
  mg::Rng rng(seed);
  if (opt.num_gaussians > n)
    throw InputError(fmt::format(
        "number of Gaussians: expected at most {} (the number of training rows), got {}", n,
        opt.num_gaussians));
  const int folds = std::min(opt.cv_folds, n);
  mg::Rng fold_rng(mg::derive_seed(seed, 77));
  const std::vector<int> fold_of = make_folds(n, folds, fold_rng);
  const std::vector<double> regs =
      opt.choose_reg_covar ? opt.reg_covar_grid : std::vector<double>{opt.em.reg_covar};

  // The default reg_covar is a prior of fixed strength: reg_covar_rows / N (em.reg_covar at
  // most, 1e-2: best on the smallest noisy sets), as a Normal-inverse-Wishart prior's weight
  // falls as 1/N. It stays unless another value's held-out GMR error is measurably lower
  // (measurably_lower: by kRegSwitchGain and two paired standard errors). Below
  // kMinRowsForRegSelection rows (folds of one or two points) the default is kept.
  constexpr double kRegSwitchGain = 0.05;
  constexpr int kMinRowsForRegSelection = 10;
  const double default_reg =
      opt.choose_reg_covar
          ? std::min(opt.em.reg_covar, std::max(*std::min_element(regs.begin(), regs.end()),
                                                opt.reg_covar_rows / static_cast<double>(n)))
          : opt.em.reg_covar;
  int best_k = opt.num_gaussians;
  double best_reg = default_reg;
  auto choose = [&](const std::vector<int>& ks) {
    Eigen::VectorXd err_default, err_other;
    double best_default = std::numeric_limits<double>::infinity(), best_other = best_default;
    int k_default = ks.front(), k_other = ks.front();
    double reg_other = default_reg;
    for (int k : ks) {
      stats::EmOptions em = opt.em;
      em.reg_covar = default_reg;
      Eigen::VectorXd e = cv_errors_or_inf(joint, num_inputs, k, folds, fold_of, seed, em);
      if (const double m = mean_or_inf(e); m < best_default * (1.0 - 1e-12)) {
        best_default = m;
        err_default = std::move(e);
        k_default = k;
      }
      if (n < kMinRowsForRegSelection) continue;
      for (auto it = regs.rbegin(); it != regs.rend(); ++it) {
        if (*it == default_reg) continue;
        em.reg_covar = *it;
        Eigen::VectorXd eo = cv_errors_or_inf(joint, num_inputs, k, folds, fold_of, seed, em);
        if (const double m = mean_or_inf(eo); m < best_other * (1.0 - 1e-2)) {
          best_other = m;
          err_other = std::move(eo);
          k_other = k;
          reg_other = *it;
        }
      }
    }
    if (!std::isfinite(best_default) && !std::isfinite(best_other))
      throw NumericalError(fmt::format(
          "GMM fit: every cross-validation fit failed (K in {}..{}, reg_covar in {}..{})",
          ks.front(), ks.back(), regs.front(), regs.back()));
    if (measurably_lower(err_other, err_default,
                         kRegSwitchGain)) {  // false when no other value fitted
      best_k = k_other;
      best_reg = reg_other;
    } else {
      best_k = k_default;
      best_reg = default_reg;
    }
  };
  if (opt.num_gaussians > 0) {
    if (regs.size() > 1) choose({opt.num_gaussians});
  } else if (opt.selection == ComponentSelection::kBic) {
    // K by BIC at the fixed em.reg_covar, then reg_covar by cross-validation at that K.
    stats::EmResult by_bic = stats::fit_gmm_bic(joint, opt.max_gaussians, rng, opt.em);
    if (regs.size() == 1) return {std::move(by_bic), default_reg};
    best_k = by_bic.gmm.num_components();
    choose({best_k});
    if (best_reg == default_reg)
      return {std::move(by_bic), default_reg};  // the same fit as without the choice
  } else {
    std::vector<int> ks;
    for (int k = 1; k <= std::min(opt.max_gaussians, n); ++k) ks.push_back(k);
    choose(ks);
  }
  stats::EmOptions em = opt.em;
  em.reg_covar = best_reg;
  return {stats::fit_gmm(joint, best_k, rng, em), best_reg};
}

}  // namespace mg::learning::detail
