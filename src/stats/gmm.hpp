#pragma once
/// Gaussian mixture models: k-means++ seeding, k-means, EM with regularised covariances, BIC.
///
/// Samples are the ROWS of an N x D matrix. Everything is deterministic given the `mg::Rng`.
/// This is the one GMM of the project: the learners and the hitting DS (SEDS) both use it.
#include <vector>

#include <Eigen/Core>

#include "core/rng.hpp"

namespace mg::stats {

/// A mixture of `K` Gaussians in `D` dimensions. A plain value type; `validate()` checks it.
struct Gmm {
  Eigen::VectorXd priors;              ///< mixing weights, (K), non-negative, sum 1
  std::vector<Eigen::VectorXd> means;  ///< K means, each (D)
  std::vector<Eigen::MatrixXd>
      covariances;  ///< K covariances, each (D x D), symmetric positive definite

  int num_components() const { return static_cast<int>(priors.size()); }
  int dim() const { return means.empty() ? 0 : static_cast<int>(means.front().size()); }
  /// Throws `mg::InputError` naming the component and quantity unless the mixture is well formed:
  /// K >= 1, consistent sizes, finite values, priors >= 0 summing to 1 (within 1e-9), covariances
  /// symmetric (relative 1e-9) and positive definite (Cholesky succeeds).
  void validate() const;
};

/// Options of `fit_gmm`. Defaults in one place; `validate()` throws `mg::InputError` naming the
/// field.
struct EmOptions {
  int max_iterations = 300;  ///< EM iterations at most (>= 1)
  double tolerance = 1e-8;   ///< stop when |LL change| <= tolerance * max(1, |LL|) (> 0)
  double reg_covar = 1e-6;   ///< added to every covariance diagonal, in data units^2 (>= 0)
  int kmeans_restarts =
      5;  ///< k-means++ seedings tried per initialisation; the lowest inertia wins (>= 1)
  int init_restarts =
      1;  ///< independent initialisations, each followed by EM; the highest final LL wins (>= 1)
  void validate() const;
};

struct EmResult {
  Gmm gmm;
  double log_likelihood = 0.0;  ///< total log-likelihood of the data under `gmm` [nats]
  int iterations = 0;           ///< EM iterations performed
  std::vector<double>
      log_likelihood_trace;  ///< LL of each successive parameter set, last = `log_likelihood`
};

/// Result of k-means (Lloyd's algorithm after k-means++ seeding).
struct KMeansResult {
  Eigen::MatrixXd centers;  ///< (K x D), one centre per row
  std::vector<int> labels;  ///< (N), index of the nearest centre of each sample
  double inertia = 0.0;     ///< sum of squared distances to the nearest centre
};

/// k-means with k-means++ seeding; the best of `restarts` seedings. Requires 1 <= K <= N.
KMeansResult kmeans(const Eigen::MatrixXd& data, int num_clusters, mg::Rng& rng, int restarts = 5,
                    int max_iterations = 100);

/// Fits a K-component GMM to the rows of `data` by EM initialised with k-means++ / k-means.
/// Requires 1 <= K <= N and finite data; throws `mg::InputError` otherwise.
EmResult fit_gmm(const Eigen::MatrixXd& data, int num_components, mg::Rng& rng,
                 const EmOptions& options = {});

/// Total log-likelihood sum_n log p(x_n) [nats] (log-sum-exp, finite far from all components).
double gmm_log_likelihood(const Gmm& gmm, const Eigen::MatrixXd& data);

/// log p(x) of one sample (D).
double gmm_log_density(const Gmm& gmm, const Eigen::VectorXd& x);

/// Posterior responsibilities p(k | x_n), (N x K), rows sum to 1 (log-sum-exp).
Eigen::MatrixXd gmm_responsibilities(const Gmm& gmm, const Eigen::MatrixXd& data);

/// Number of free parameters of a full-covariance GMM: (K-1) + K D + K D (D+1) / 2.
int gmm_num_parameters(int num_components, int dim);

/// Bayesian information criterion -2 LL + p ln N (lower is better).
double gmm_bic(const Gmm& gmm, const Eigen::MatrixXd& data);

/// Fits K = 1..max_components and returns the fit with the lowest BIC (K is capped at N).
EmResult fit_gmm_bic(const Eigen::MatrixXd& data, int max_components, mg::Rng& rng,
                     const EmOptions& options = {});

}  // namespace mg::stats
