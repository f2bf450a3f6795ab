#pragma once
/// Gaussian mixture regression: condition a GMM on any subset of its dimensions.
///
/// p(out | in) = sum_k h_k(in) N(out; A_k in + b_k, C_k), with h_k the responsibilities of the
/// input marginals (log-sum-exp, so they stay finite far from every component: the component
/// with the highest log-weight then takes over and its linear trend continues). The predictive
/// covariance is the full mixture covariance (law of total covariance):
/// sum_k h_k (C_k + (m_k - m)(m_k - m)^T).
#include <vector>

#include <Eigen/Core>

#include "stats/gmm.hpp"

namespace mg::stats {

struct GmrPrediction {
  Eigen::VectorXd mean;        ///< E[out | in], (O)
  Eigen::MatrixXd covariance;  ///< Cov[out | in], (O x O)
};

/// A GMM prepared for repeated conditioning on fixed input/output dimensions. Immutable after
/// construction; each thread owns its `Workspace`. `predict_mean`, `predict` and
/// `responsibilities` are real-time safe: no heap allocation, no exceptions (given a workspace
/// from `make_workspace()` and correctly sized arguments).
class GmrConditioner {
 public:
  /// Preallocated scratch space for one caller.
  struct Workspace {
    Eigen::VectorXd diff;        ///< (I)
    Eigen::VectorXd log_weight;  ///< (K)
    Eigen::MatrixXd cond_means;  ///< (O x K)
    Eigen::VectorXd delta;       ///< (O)
  };

  /// Validates the GMM and the dimension lists (distinct, in range, outputs non-empty; inputs may
  /// be empty, which gives the marginal of the outputs). Throws `mg::InputError`.
  GmrConditioner(const Gmm& gmm, std::vector<int> input_dims, std::vector<int> output_dims);

  Workspace make_workspace() const;

  /// Conditional mean into `out` (O). `x` is (I).
  void predict_mean(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> out,
                    Workspace& ws) const;
  /// Conditional mean (O) and covariance (O x O).
  void predict(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> mean,
               Eigen::Ref<Eigen::MatrixXd> covariance, Workspace& ws) const;
  /// Responsibilities h_k(x), (K), summing to 1.
  void responsibilities(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> h,
                        Workspace& ws) const;

  /// Allocating convenience form of `predict`.
  GmrPrediction predict(const Eigen::VectorXd& x) const;

  int num_components() const { return static_cast<int>(gains_.size()); }
  int input_dim() const { return static_cast<int>(input_dims_.size()); }
  int output_dim() const { return static_cast<int>(output_dims_.size()); }
  const std::vector<int>& input_dims() const { return input_dims_; }
  const std::vector<int>& output_dims() const { return output_dims_; }
  /// A_k = Sigma_OI Sigma_II^-1, (O x I).
  const Eigen::MatrixXd& gain(int k) const { return gains_[static_cast<std::size_t>(k)]; }
  /// b_k = mu_O - A_k mu_I, (O).
  const Eigen::VectorXd& offset(int k) const { return offsets_[static_cast<std::size_t>(k)]; }
  /// C_k = Sigma_OO - A_k Sigma_IO, (O x O).
  const Eigen::MatrixXd& conditional_covariance(int k) const {
    return cond_covs_[static_cast<std::size_t>(k)];
  }

 private:
  // Log-weights log(pi_k N(x; mu_I, Sigma_II)) into ws.log_weight; turns them into h_k in place.
  void compute_weights(const Eigen::Ref<const Eigen::VectorXd>& x, Workspace& ws) const;

  std::vector<int> input_dims_;
  std::vector<int> output_dims_;
  std::vector<Eigen::VectorXd> input_means_;  // mu_I^k, (I)
  std::vector<Eigen::MatrixXd> input_chol_;   // lower Cholesky of Sigma_II^k, (I x I)
  Eigen::VectorXd log_norm_;  // log pi_k - 1/2 (I log 2 pi + log det Sigma_II^k), (K)
  std::vector<Eigen::MatrixXd> gains_;
  std::vector<Eigen::VectorXd> offsets_;
  std::vector<Eigen::MatrixXd> cond_covs_;
};

/// One-shot conditioning: E[out | in = x] and Cov[out | in = x].
GmrPrediction gmr_predict(const Gmm& gmm, const std::vector<int>& input_dims,
                          const std::vector<int>& output_dims, const Eigen::VectorXd& x);

}  // namespace mg::stats
