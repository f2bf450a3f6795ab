#include "stats/gmr.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "core/error.hpp"
#include "stats/linalg.hpp"

namespace mg::stats {
namespace {

Eigen::MatrixXd sub_matrix(const Eigen::MatrixXd& m, const std::vector<int>& rows,
                           const std::vector<int>& cols) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()),
                      static_cast<Eigen::Index>(cols.size()));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < cols.size(); ++j)
      out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = m(rows[i], cols[j]);
  return out;
}

Eigen::VectorXd sub_vector(const Eigen::VectorXd& v, const std::vector<int>& idx) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(idx.size()));
  for (std::size_t i = 0; i < idx.size(); ++i) out(static_cast<Eigen::Index>(i)) = v(idx[i]);
  return out;
}

void check_dims(const std::vector<int>& input_dims, const std::vector<int>& output_dims, int dim) {
  if (output_dims.empty())
    throw InputError("GMR: output dimensions: expected at least one, got none");
  std::vector<bool> used(static_cast<std::size_t>(dim), false);
  auto check = [&](const std::vector<int>& dims, const char* what) {
    for (int d : dims) {
      if (d < 0 || d >= dim)
        throw InputError(
            fmt::format("GMR: {} dimension: expected 0..{}, got {}", what, dim - 1, d));
      if (used[static_cast<std::size_t>(d)])
        throw InputError(fmt::format(
            "GMR: dimension {} is used twice (inputs and outputs must be distinct)", d));
      used[static_cast<std::size_t>(d)] = true;
    }
  };
  check(input_dims, "input");
  check(output_dims, "output");
}

}  // namespace

GmrConditioner::GmrConditioner(const Gmm& gmm, std::vector<int> input_dims,
                               std::vector<int> output_dims)
    : input_dims_(std::move(input_dims)), output_dims_(std::move(output_dims)) {
  gmm.validate();
  check_dims(input_dims_, output_dims_, gmm.dim());
  const int k_count = gmm.num_components();
  const double in_dim = static_cast<double>(input_dims_.size());
  log_norm_.resize(k_count);
  for (int k = 0; k < k_count; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const Eigen::MatrixXd& cov = gmm.covariances[ku];
    const Eigen::MatrixXd s_ii = sub_matrix(cov, input_dims_, input_dims_);
    const Eigen::MatrixXd s_oi = sub_matrix(cov, output_dims_, input_dims_);
    const Eigen::MatrixXd s_oo = sub_matrix(cov, output_dims_, output_dims_);
    const Eigen::VectorXd mu_i = sub_vector(gmm.means[ku], input_dims_);
    const Eigen::VectorXd mu_o = sub_vector(gmm.means[ku], output_dims_);
    Eigen::MatrixXd l = input_dims_.empty() ? Eigen::MatrixXd(0, 0) : robust_cholesky(s_ii);
    // A = S_oi S_ii^-1 = (S_ii^-1 S_io)^T via two triangular solves.
    Eigen::MatrixXd a_t = s_oi.transpose();
    if (!input_dims_.empty()) {
      l.triangularView<Eigen::Lower>().solveInPlace(a_t);
      l.transpose().triangularView<Eigen::Upper>().solveInPlace(a_t);
    }
    Eigen::MatrixXd a = a_t.transpose();
    Eigen::MatrixXd c = s_oo - a * s_oi.transpose();
    c = 0.5 * (c + c.transpose());
    const double log_det = input_dims_.empty() ? 0.0 : 2.0 * l.diagonal().array().log().sum();
    log_norm_(k) =
        std::log(gmm.priors(k)) - 0.5 * (in_dim * std::log(2.0 * std::numbers::pi) + log_det);
    offsets_.push_back(mu_o - a * mu_i);
    gains_.push_back(std::move(a));
    cond_covs_.push_back(std::move(c));
    input_means_.push_back(mu_i);
    input_chol_.push_back(std::move(l));
  }
}

GmrConditioner::Workspace GmrConditioner::make_workspace() const {
  Workspace ws;
  ws.diff.resize(input_dim());
  ws.log_weight.resize(num_components());
  ws.cond_means.resize(output_dim(), num_components());
  ws.delta.resize(output_dim());
  return ws;
}

void GmrConditioner::compute_weights(const Eigen::Ref<const Eigen::VectorXd>& x,
                                     Workspace& ws) const {
  const int k_count = num_components();
  for (int k = 0; k < k_count; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    double maha = 0.0;
    if (!input_dims_.empty()) {
      ws.diff = x - input_means_[ku];
      input_chol_[ku].triangularView<Eigen::Lower>().solveInPlace(ws.diff);
      maha = ws.diff.squaredNorm();
    }
    ws.log_weight(k) = log_norm_(k) - 0.5 * maha;
  }
  const double lse = log_sum_exp(ws.log_weight);
  if (std::isfinite(lse)) {
    ws.log_weight = (ws.log_weight.array() - lse).exp();
  } else {
    // Only reachable with non-finite x: fall back to the component with the largest log-weight
    // (or the first) rather than producing NaN.
    Eigen::Index best = 0;
    if (ws.log_weight.allFinite()) ws.log_weight.maxCoeff(&best);
    ws.log_weight.setZero();
    ws.log_weight(best) = 1.0;
  }
}

void GmrConditioner::responsibilities(const Eigen::Ref<const Eigen::VectorXd>& x,
                                      Eigen::Ref<Eigen::VectorXd> h, Workspace& ws) const {
  compute_weights(x, ws);
  h = ws.log_weight;
}

void GmrConditioner::predict_mean(const Eigen::Ref<const Eigen::VectorXd>& x,
                                  Eigen::Ref<Eigen::VectorXd> out, Workspace& ws) const {
  compute_weights(x, ws);
  out.setZero();
  for (int k = 0; k < num_components(); ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const double h = ws.log_weight(k);
    if (h == 0.0) continue;
    ws.delta = offsets_[ku];
    ws.delta.noalias() += gains_[ku] * x;
    out += h * ws.delta;
  }
}

void GmrConditioner::predict(const Eigen::Ref<const Eigen::VectorXd>& x,
                             Eigen::Ref<Eigen::VectorXd> mean,
                             Eigen::Ref<Eigen::MatrixXd> covariance, Workspace& ws) const {
  compute_weights(x, ws);
  mean.setZero();
  for (int k = 0; k < num_components(); ++k) {
    const auto ku = static_cast<std::size_t>(k);
    ws.cond_means.col(k) = offsets_[ku];
    ws.cond_means.col(k).noalias() += gains_[ku] * x;
    mean += ws.log_weight(k) * ws.cond_means.col(k);
  }
  covariance.setZero();
  for (int k = 0; k < num_components(); ++k) {
    const double h = ws.log_weight(k);
    if (h == 0.0) continue;
    ws.delta = ws.cond_means.col(k) - mean;
    covariance += h * cond_covs_[static_cast<std::size_t>(k)];
    covariance.noalias() += h * ws.delta * ws.delta.transpose();
  }
}

GmrPrediction GmrConditioner::predict(const Eigen::VectorXd& x) const {
  if (x.size() != input_dim())
    throw InputError(
        fmt::format("GMR: query: expected {} input values, got {}", input_dim(), x.size()));
  GmrPrediction p;
  p.mean.resize(output_dim());
  p.covariance.resize(output_dim(), output_dim());
  Workspace ws = make_workspace();
  predict(x, p.mean, p.covariance, ws);
  return p;
}

GmrPrediction gmr_predict(const Gmm& gmm, const std::vector<int>& input_dims,
                          const std::vector<int>& output_dims, const Eigen::VectorXd& x) {
  return GmrConditioner(gmm, input_dims, output_dims).predict(x);
}

}  // namespace mg::stats
