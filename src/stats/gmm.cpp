#include "stats/gmm.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>
#include <Eigen/Cholesky>

#include "core/error.hpp"
#include "stats/linalg.hpp"

namespace mg::stats {
namespace {

void require_data(const Eigen::MatrixXd& data, int num_components, const char* who) {
  if (data.rows() == 0 || data.cols() == 0)
    throw InputError(fmt::format("{}: expected a non-empty N x D data matrix, got {} x {}", who,
                                 data.rows(), data.cols()));
  if (!data.allFinite())
    throw InputError(fmt::format("{}: data: expected finite values, got NaN or inf", who));
  if (num_components < 1 || num_components > data.rows())
    throw InputError(
        fmt::format("{}: number of components: expected 1..{} (the number of samples), got {}", who,
                    data.rows(), num_components));
}

// Log densities log(pi_k N(x_n; mu_k, Sigma_k)), (N x K).
Eigen::MatrixXd weighted_log_densities(const Gmm& gmm, const Eigen::MatrixXd& data) {
  const int n = static_cast<int>(data.rows());
  const int d = static_cast<int>(data.cols());
  const int k_count = gmm.num_components();
  Eigen::MatrixXd out(n, k_count);
  const double log_2pi = std::log(2.0 * std::numbers::pi);
  for (int k = 0; k < k_count; ++k) {
    const Eigen::MatrixXd l = robust_cholesky(gmm.covariances[static_cast<std::size_t>(k)]);
    const double log_det = 2.0 * l.diagonal().array().log().sum();
    Eigen::MatrixXd diff =
        (data.rowwise() - gmm.means[static_cast<std::size_t>(k)].transpose()).transpose();
    l.triangularView<Eigen::Lower>().solveInPlace(diff);
    const double log_prior = std::log(gmm.priors(k));
    out.col(k) = (-0.5 * (diff.colwise().squaredNorm().array() + d * log_2pi + log_det) + log_prior)
                     .matrix()
                     .transpose();
  }
  return out;
}

// Row-wise log-sum-exp of (N x K); -inf rows (all components impossible) stay -inf.
Eigen::VectorXd row_log_sum_exp(const Eigen::MatrixXd& m) {
  Eigen::VectorXd out(m.rows());
  for (Eigen::Index i = 0; i < m.rows(); ++i) out(i) = log_sum_exp(m.row(i));
  return out;
}

double uniform01(mg::Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// k-means++ seeding (Arthur & Vassilvitskii 2007).
Eigen::MatrixXd kmeans_pp_seed(const Eigen::MatrixXd& data, int k_count, mg::Rng& rng) {
  const Eigen::Index n = data.rows();
  Eigen::MatrixXd centers(k_count, data.cols());
  Eigen::Index first = std::min<Eigen::Index>(
      static_cast<Eigen::Index>(uniform01(rng) * static_cast<double>(n)), n - 1);
  centers.row(0) = data.row(first);
  Eigen::VectorXd d2 = (data.rowwise() - centers.row(0)).rowwise().squaredNorm();
  for (int k = 1; k < k_count; ++k) {
    const double total = d2.sum();
    Eigen::Index pick = n - 1;
    if (total > 0.0) {
      const double u = uniform01(rng) * total;
      double acc = 0.0;
      for (Eigen::Index i = 0; i < n; ++i) {
        acc += d2(i);
        if (acc > u) {
          pick = i;
          break;
        }
      }
    } else {
      pick = std::min<Eigen::Index>(
          static_cast<Eigen::Index>(uniform01(rng) * static_cast<double>(n)), n - 1);
    }
    centers.row(k) = data.row(pick);
    d2 = d2.cwiseMin((data.rowwise() - centers.row(k)).rowwise().squaredNorm());
  }
  return centers;
}

KMeansResult lloyd(const Eigen::MatrixXd& data, Eigen::MatrixXd centers, int max_iterations) {
  const Eigen::Index n = data.rows();
  const Eigen::Index k_count = centers.rows();
  KMeansResult r;
  r.labels.assign(static_cast<std::size_t>(n), -1);
  for (int it = 0; it < max_iterations; ++it) {
    bool changed = false;
    r.inertia = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Index best = 0;
      const double dist = (centers.rowwise() - data.row(i)).rowwise().squaredNorm().minCoeff(&best);
      r.inertia += dist;
      if (r.labels[static_cast<std::size_t>(i)] != static_cast<int>(best)) {
        r.labels[static_cast<std::size_t>(i)] = static_cast<int>(best);
        changed = true;
      }
    }
    if (!changed) break;
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(k_count, data.cols());
    Eigen::VectorXd counts = Eigen::VectorXd::Zero(k_count);
    for (Eigen::Index i = 0; i < n; ++i) {
      sums.row(r.labels[static_cast<std::size_t>(i)]) += data.row(i);
      counts(r.labels[static_cast<std::size_t>(i)]) += 1.0;
    }
    // An emptied cluster keeps its centre.
    for (Eigen::Index k = 0; k < k_count; ++k)
      if (counts(k) > 0.0) centers.row(k) = sums.row(k) / counts(k);
  }
  r.centers = std::move(centers);
  return r;
}

// M-step from responsibilities (N x K). Components with (almost) no mass keep their old parameters.
void m_step(const Eigen::MatrixXd& data, const Eigen::MatrixXd& resp, double reg_covar, Gmm& gmm) {
  const Eigen::Index n = data.rows();
  const Eigen::Index d = data.cols();
  const Eigen::Index k_count = resp.cols();
  const Eigen::VectorXd nk = resp.colwise().sum().transpose();
  gmm.priors = nk / nk.sum();
  gmm.means.resize(static_cast<std::size_t>(k_count), Eigen::VectorXd::Zero(d));
  gmm.covariances.resize(static_cast<std::size_t>(k_count), Eigen::MatrixXd::Identity(d, d));
  const double dead = 1e-12 * static_cast<double>(n);
  for (Eigen::Index k = 0; k < k_count; ++k) {
    if (nk(k) <= dead) continue;
    const auto ku = static_cast<std::size_t>(k);
    gmm.means[ku] = (data.transpose() * resp.col(k)) / nk(k);
    const Eigen::MatrixXd centred = data.rowwise() - gmm.means[ku].transpose();
    Eigen::MatrixXd cov = (centred.transpose() * resp.col(k).asDiagonal() * centred) / nk(k);
    cov = 0.5 * (cov + cov.transpose());
    cov.diagonal().array() += reg_covar;
    gmm.covariances[ku] = std::move(cov);
  }
}

}  // namespace

void Gmm::validate() const {
  const int k_count = num_components();
  if (k_count < 1) throw InputError("GMM: expected at least 1 component, got 0");
  if (static_cast<int>(means.size()) != k_count || static_cast<int>(covariances.size()) != k_count)
    throw InputError(
        fmt::format("GMM: expected {} means and covariances (one per prior), got {} and {}",
                    k_count, means.size(), covariances.size()));
  const int d = dim();
  if (d < 1) throw InputError("GMM: expected dimension >= 1, got 0");
  double sum = 0.0;
  for (int k = 0; k < k_count; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    if (!std::isfinite(priors(k)) || priors(k) < 0.0)
      throw InputError(fmt::format("GMM component {}: prior: expected a finite number >= 0, got {}",
                                   k, priors(k)));
    sum += priors(k);
    if (means[ku].size() != d)
      throw InputError(fmt::format("GMM component {}: mean: expected dimension {}, got {}", k, d,
                                   means[ku].size()));
    if (!means[ku].allFinite())
      throw InputError(fmt::format("GMM component {}: mean: expected finite values", k));
    const Eigen::MatrixXd& c = covariances[ku];
    if (c.rows() != d || c.cols() != d)
      throw InputError(fmt::format("GMM component {}: covariance: expected {} x {}, got {} x {}", k,
                                   d, d, c.rows(), c.cols()));
    if (!c.allFinite())
      throw InputError(fmt::format("GMM component {}: covariance: expected finite values", k));
    const double asym = (c - c.transpose()).cwiseAbs().maxCoeff();
    if (asym > 1e-9 * std::max(1.0, c.cwiseAbs().maxCoeff()))
      throw InputError(fmt::format(
          "GMM component {}: covariance: expected a symmetric matrix, asymmetry {}", k, asym));
    Eigen::LLT<Eigen::MatrixXd> llt(c);
    if (llt.info() != Eigen::Success)
      throw InputError(fmt::format(
          "GMM component {}: covariance: expected positive definite, Cholesky failed", k));
  }
  if (std::abs(sum - 1.0) > 1e-9)
    throw InputError(fmt::format("GMM: priors: expected a sum of 1, got {}", sum));
}

void EmOptions::validate() const {
  if (max_iterations < 1)
    throw InputError(
        fmt::format("EM options: max_iterations: expected >= 1, got {}", max_iterations));
  if (!(tolerance > 0.0) || !std::isfinite(tolerance))
    throw InputError(
        fmt::format("EM options: tolerance: expected a positive number, got {}", tolerance));
  if (!(reg_covar >= 0.0) || !std::isfinite(reg_covar))
    throw InputError(
        fmt::format("EM options: reg_covar: expected a number >= 0, got {}", reg_covar));
  if (kmeans_restarts < 1)
    throw InputError(
        fmt::format("EM options: kmeans_restarts: expected >= 1, got {}", kmeans_restarts));
  if (init_restarts < 1)
    throw InputError(
        fmt::format("EM options: init_restarts: expected >= 1, got {}", init_restarts));
}

KMeansResult kmeans(const Eigen::MatrixXd& data, int num_clusters, mg::Rng& rng, int restarts,
                    int max_iterations) {
  require_data(data, num_clusters, "k-means");
  KMeansResult best;
  best.inertia = std::numeric_limits<double>::infinity();
  for (int r = 0; r < std::max(1, restarts); ++r) {
    KMeansResult res =
        lloyd(data, kmeans_pp_seed(data, num_clusters, rng), std::max(1, max_iterations));
    if (res.inertia < best.inertia) best = std::move(res);
  }
  // Every restart non-finite (data near the double range: squared distances overflow): no
  // clustering to return, and an empty one would be read out of bounds by the caller.
  if (best.labels.empty())
    throw mg::NumericalError(
        fmt::format("k-means: every squared distance overflowed (|values| up to {:g}); "
                    "rescale the data",
                    data.cwiseAbs().maxCoeff()));
  return best;
}

namespace {

// One initialisation (k-means) followed by EM.
EmResult run_em(const Eigen::MatrixXd& data, int num_components, mg::Rng& rng,
                const EmOptions& options) {
  const Eigen::Index n = data.rows();
  const Eigen::Index d = data.cols();
  const KMeansResult km = kmeans(data, num_components, rng, options.kmeans_restarts);

  // Initial parameters from the hard k-means assignment. Clusters too small for a covariance get
  // the overall covariance shrunk by K, so no component starts as a needle.
  EmResult result;
  Gmm& gmm = result.gmm;
  Eigen::MatrixXd resp = Eigen::MatrixXd::Zero(n, num_components);
  for (Eigen::Index i = 0; i < n; ++i) resp(i, km.labels[static_cast<std::size_t>(i)]) = 1.0;
  gmm.means.assign(static_cast<std::size_t>(num_components), Eigen::VectorXd::Zero(d));
  gmm.covariances.assign(static_cast<std::size_t>(num_components), Eigen::MatrixXd::Identity(d, d));
  for (int k = 0; k < num_components; ++k)
    gmm.means[static_cast<std::size_t>(k)] = km.centers.row(k).transpose();
  m_step(data, resp, options.reg_covar, gmm);
  const Eigen::RowVectorXd overall_mean = data.colwise().mean();
  const Eigen::MatrixXd centred = data.rowwise() - overall_mean;
  Eigen::MatrixXd overall_cov = centred.transpose() * centred / static_cast<double>(n);
  overall_cov /= static_cast<double>(num_components);
  overall_cov.diagonal().array() +=
      std::max(options.reg_covar, 1e-12 * std::max(1.0, overall_cov.diagonal().maxCoeff()));
  const Eigen::VectorXd counts = resp.colwise().sum().transpose();
  for (int k = 0; k < num_components; ++k)
    if (counts(k) < static_cast<double>(d) + 1.0)
      gmm.covariances[static_cast<std::size_t>(k)] = overall_cov;
  // Priors never start at exactly 0 (log 0), even if k-means left a cluster empty.
  gmm.priors = (counts.array() + 1e-3).matrix();
  gmm.priors /= gmm.priors.sum();

  double previous = -std::numeric_limits<double>::infinity();
  for (int it = 0; it < options.max_iterations; ++it) {
    // E-step with log-sum-exp.
    const Eigen::MatrixXd logp = weighted_log_densities(gmm, data);
    const Eigen::VectorXd lse = row_log_sum_exp(logp);
    const double ll = lse.sum();
    result.log_likelihood_trace.push_back(ll);
    if (it > 0 && std::abs(ll - previous) <= options.tolerance * std::max(1.0, std::abs(ll))) break;
    previous = ll;
    resp = (logp.colwise() - lse).array().exp().matrix();
    m_step(data, resp, options.reg_covar, gmm);
    result.iterations = it + 1;
  }
  result.log_likelihood = gmm_log_likelihood(gmm, data);
  if (result.log_likelihood_trace.empty() ||
      result.log_likelihood_trace.back() != result.log_likelihood)
    result.log_likelihood_trace.push_back(result.log_likelihood);
  return result;
}

}  // namespace

EmResult fit_gmm(const Eigen::MatrixXd& data, int num_components, mg::Rng& rng,
                 const EmOptions& options) {
  options.validate();
  require_data(data, num_components, "GMM fit");
  EmResult best;
  best.log_likelihood = -std::numeric_limits<double>::infinity();
  for (int r = 0; r < options.init_restarts; ++r) {
    EmResult res = run_em(data, num_components, rng, options);
    if (r == 0 || res.log_likelihood > best.log_likelihood) best = std::move(res);
  }
  if (!std::isfinite(best.log_likelihood))
    throw NumericalError(
        fmt::format("GMM fit: expected a finite log-likelihood, got {}", best.log_likelihood));
  return best;
}

double gmm_log_likelihood(const Gmm& gmm, const Eigen::MatrixXd& data) {
  if (data.cols() != gmm.dim())
    throw InputError(fmt::format("GMM log-likelihood: data: expected {} columns, got {}", gmm.dim(),
                                 data.cols()));
  return row_log_sum_exp(weighted_log_densities(gmm, data)).sum();
}

double gmm_log_density(const Gmm& gmm, const Eigen::VectorXd& x) {
  return gmm_log_likelihood(gmm, x.transpose());
}

Eigen::MatrixXd gmm_responsibilities(const Gmm& gmm, const Eigen::MatrixXd& data) {
  if (data.cols() != gmm.dim())
    throw InputError(fmt::format("GMM responsibilities: data: expected {} columns, got {}",
                                 gmm.dim(), data.cols()));
  const Eigen::MatrixXd logp = weighted_log_densities(gmm, data);
  const Eigen::VectorXd lse = row_log_sum_exp(logp);
  return (logp.colwise() - lse).array().exp().matrix();
}

int gmm_num_parameters(int num_components, int dim) {
  return (num_components - 1) + num_components * dim + num_components * dim * (dim + 1) / 2;
}

double gmm_bic(const Gmm& gmm, const Eigen::MatrixXd& data) {
  return -2.0 * gmm_log_likelihood(gmm, data) +
         gmm_num_parameters(gmm.num_components(), gmm.dim()) *
             std::log(static_cast<double>(data.rows()));
}

EmResult fit_gmm_bic(const Eigen::MatrixXd& data, int max_components, mg::Rng& rng,
                     const EmOptions& options) {
  if (max_components < 1)
    throw InputError(
        fmt::format("GMM BIC selection: max components: expected >= 1, got {}", max_components));
  require_data(data, 1, "GMM BIC selection");
  const int k_max = std::min<int>(max_components, static_cast<int>(data.rows()));
  EmResult best;
  double best_bic = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= k_max; ++k) {
    EmResult r = fit_gmm(data, k, rng, options);
    const double bic = gmm_bic(r.gmm, data);
    if (bic < best_bic) {
      best_bic = bic;
      best = std::move(r);
    }
  }
  return best;
}

}  // namespace mg::stats
