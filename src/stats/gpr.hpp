#pragma once
/// Gaussian process regression for one scalar output (thesis 3.3.1, GPML 2.2 and 5.4).
///
/// Zero-mean GP on the standardised output (y - mean) / scale with the ARD squared-exponential
/// covariance k(a, b) = sf^2 exp(-1/2 sum_i (a_i - b_i)^2 / l_i^2) plus Gaussian noise sn^2.
/// Far from the data the prediction reverts to the prior mean, i.e. the training-output mean.
/// Hyperparameters maximise the log marginal likelihood (analytic gradient, NLopt L-BFGS in log
/// space, within bounds, several starts). Inputs are used in their own units (no scaling), so
/// length scales are in input units; signal and noise standard deviations in output units.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/rng.hpp"

namespace mg::stats {

struct GpHyperparameters {
  Eigen::VectorXd length_scales;  ///< l_i, (D), input units
  double signal_std = 1.0;        ///< sf, output units
  double noise_std = 0.1;         ///< sn, output units
};

/// Options of `fit_gpr`. Zero / empty entries mean "derive from the data":
/// length scales start at the input column's standard deviation s_i (1 if the column is
/// constant) within [1e-2 s_i, 1e2 s_i]; sf starts at the output std s_y within
/// [1e-2 s_y, 1e2 s_y]; sn starts at 0.1 s_y within [1e-3 s_y, 2 s_y].
struct GprOptions {
  int restarts = 10;  ///< optimiser starts (>= 1): the initial guess, then log-uniform draws
  Eigen::VectorXd initial_length_scales;  ///< (D) or (1) broadcast; empty = default
  double initial_signal_std = 0.0;        ///< output units; 0 = default
  double initial_noise_std = 0.0;         ///< output units; 0 = default
  std::array<double, 2> length_scale_bounds{
      0.0, 0.0};  ///< input units, applied to every dim; {0,0} = default
  std::array<double, 2> signal_std_bounds{0.0, 0.0};  ///< output units; {0,0} = default
  std::array<double, 2> noise_std_bounds{0.0, 0.0};   ///< output units; {0,0} = default
  int max_evaluations = 400;                          ///< per start
  bool optimize = true;                               ///< false: use the initial guess as is
  void validate() const;                              ///< throws `mg::InputError` naming the field
};

/// A trained GP: the training set, the hyperparameters and the factorisation they imply.
/// Immutable; build it with `make_gp_model` or `fit_gpr`.
struct GpModel {
  Eigen::MatrixXd inputs;     ///< (N x D) training inputs, one per row
  Eigen::VectorXd targets;    ///< (N) training outputs, output units
  GpHyperparameters hyper;    ///< in data units
  double output_mean = 0.0;   ///< prior mean of the output (training mean)
  double output_scale = 1.0;  ///< output standardisation scale (training std, 1 if constant)
  // Derived (recomputed by make_gp_model, never stored in files):
  Eigen::MatrixXd chol;   ///< lower Cholesky factor of K + (sn^2 + jitter) I, standardised units
  Eigen::VectorXd alpha;  ///< (K + sn^2 I)^-1 y_standardised
  double jitter = 0.0;    ///< extra diagonal added for the Cholesky, standardised units^2
  double log_marginal_likelihood = 0.0;  ///< log p(y | X, hyper) in output units [nats]

  int dim() const { return static_cast<int>(inputs.cols()); }
  int size() const { return static_cast<int>(inputs.rows()); }
};

/// Predictive distribution at one input.
struct GpPrediction {
  double mean = 0.0;             ///< output units
  double latent_variance = 0.0;  ///< variance of f(x), output units^2
  double noise_variance =
      0.0;  ///< sn^2, output units^2; the variance of an observation y is the sum
  double variance() const { return latent_variance + noise_variance; }
};

/// Scratch space for allocation-free prediction: `make_gp_workspace(model)`.
struct GpWorkspace {
  Eigen::VectorXd k_star;  ///< (N)
  Eigen::VectorXd diff;    ///< (D)
};
GpWorkspace make_gp_workspace(const GpModel& model);

/// Builds the model (Cholesky with jitter, alpha, log marginal likelihood) for given
/// hyperparameters. Throws `mg::InputError` on inconsistent sizes or non-finite values.
GpModel make_gp_model(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& targets,
                      const GpHyperparameters& hyper);

/// Fits the hyperparameters (see `GprOptions`) and returns the model. Needs N >= 1.
GpModel fit_gpr(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& targets, mg::Rng& rng,
                const GprOptions& options = {});

/// Predicts at `x` (D). Never NaN for finite x; allocation-free with a workspace.
GpPrediction gp_predict(const GpModel& model, const Eigen::Ref<const Eigen::VectorXd>& x,
                        GpWorkspace& ws);
GpPrediction gp_predict(const GpModel& model, const Eigen::VectorXd& x);

/// Log marginal likelihood of standardised targets `y` under log-hyperparameters
/// `log_params` = (log l_1..log l_D, log sf, log sn) (all in the same units as `inputs`, `y`),
/// with its gradient w.r.t. `log_params` if `gradient` is non-null. Returns -inf if the
/// covariance cannot be factorised. Exposed for tests (gradient check) and tools.
double gp_log_marginal_likelihood(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& y,
                                  const Eigen::VectorXd& log_params,
                                  Eigen::VectorXd* gradient = nullptr);

}  // namespace mg::stats
