#pragma once
/// SEDS (Khansari-Zadeh & Billard 2011): a GMM over (x, xdot) whose GMR `xdot = f(x)` is globally
/// asymptotically stable at the attractor.
///
/// Everything here works in the TARGET frame: `y = x - x*`, so the attractor is the origin and
/// the first stability condition `b_k = -A_k x*` reads `b_k = 0`. It is built into the
/// parameterisation: each component is stored in conditional form
///   p(y, ydot | k) = N(y; mu_k, Sigma_k) N(ydot; A_k y, C_k),
/// which is exactly a joint Gaussian with mean (mu_k, A_k mu_k) and covariance
///   [[Sigma_k, Sigma_k A_k^T], [A_k Sigma_k, C_k + A_k Sigma_k A_k^T]],
/// so `A_k = Sigma_ydot,y Sigma_y^-1` and `b_k = mu_ydot - A_k mu_y = 0` hold by construction. The
/// second condition, `A_k + A_k^T` negative definite, is an explicit inequality constraint
/// `lambda_max(A_k + A_k^T) <= -margin` handed to NLopt (SLSQP) with its analytic gradient
/// `d lambda_max / d A = 2 v v^T`.
///
/// Parameter vector (per component, in this order): prior logit w (priors = softmax(w)), mu (3),
/// log-Cholesky of Sigma (6: L00, L10, L11, L20, L21, L22 with the diagonal as log), A (9,
/// column-major), and for the likelihood objective the log-Cholesky of C (6).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stats/gmm.hpp"

namespace mg::ds {

enum class SedsObjective {
  kLikelihood,  ///< mean negative log-likelihood of (y, ydot) under the joint GMM [nats]
  kMse,         ///< velocity error 1/(2N) sum |f(y_n) - ydot_n|^2 [m^2/s^2]
};

/// Parses "likelihood" | "mse" (InputError otherwise).
SedsObjective parse_seds_objective(const std::string& name);
std::string to_string(SedsObjective objective);

/// One SEDS component in conditional form, target frame.
struct SedsComponent {
  double prior = 1.0;
  Eigen::Vector3d mu = Eigen::Vector3d::Zero();         ///< position mean [m]
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Identity();  ///< position covariance [m^2]
  Eigen::Matrix3d a = -Eigen::Matrix3d::Identity();     ///< dynamics matrix [1/s]
  Eigen::Matrix3d c = Eigen::Matrix3d::Identity();      ///< velocity covariance given y [m^2/s^2]
};

/// Training samples in the target frame, one per column.
struct SedsData {
  Eigen::Matrix3Xd y;     ///< positions relative to x* [m]
  Eigen::Matrix3Xd ydot;  ///< velocities [m/s]
  Eigen::Index size() const { return y.cols(); }
};

/// Upper bound on K: the fit costs about evaluations x N x K^2 (K = 12: ~1 min on 300 samples);
/// beyond it a fit does not finish in reasonable time and never improves a hitting motion.
inline constexpr int kMaxSedsGaussians = 12;

struct SedsOptions {
  int gaussians = 4;  ///< K >= 1
  SedsObjective objective = SedsObjective::kLikelihood;
  std::uint64_t seed = 1;            ///< for k-means++ / EM
  int max_evaluations = 1500;        ///< NLopt objective evaluations at most
  double relative_tolerance = 1e-7;  ///< NLopt ftol_rel
  double margin = 1e-4;              ///< required: lambda_max(A+A^T) <= -margin [1/s]
  double optimizer_margin = 1e-2;    ///< margin used inside the optimiser (stricter) [1/s]
  double covariance_floor = 1e-6;    ///< added to every covariance diagonal (units^2)
  /// Bound on every entry of A_k [1/s] (box constraint in the optimiser; 0 = none). Without it
  /// the optimiser can drive A_k of little-used components (and of clean, noise-free data) to
  /// 1e2..1e6, and the joint covariance C_k + A_k Sigma_k A_k^T loses positive definiteness to
  /// round-off. The hitting-model fit retries with 500 1/s (a 2 ms time constant) when that
  /// happens (see fit_hitting_model).
  double max_rate = 0.0;
  /// Called after every objective evaluation with the count so far (progress display; may be
  /// empty).
  std::function<void(int evaluations)> on_evaluation;
  void validate() const;
};

struct SedsResult {
  std::vector<SedsComponent> components;
  double initial_objective = 0.0;  ///< objective at the feasible initial guess
  double final_objective = 0.0;
  int evaluations = 0;           ///< objective evaluations used
  std::string optimizer_status;  ///< NLopt's result, or why the best feasible point was taken
  double max_eigenvalue = 0.0;   ///< max over k of lambda_max(A_k + A_k^T) [1/s]
  std::vector<std::string>
      notes;  ///< what the fit did on its own (components dropped), for the user
};

/// Largest eigenvalue of `A + A^T` (< 0 means the stability condition holds for this component).
double stability_eigenvalue(const Eigen::Matrix3d& a);

/// Number of parameters for K components.
int seds_num_parameters(int gaussians, SedsObjective objective);
Eigen::VectorXd pack_seds(const std::vector<SedsComponent>& components, SedsObjective objective,
                          double covariance_floor);
/// Inverse of `pack_seds`; for kMse the velocity covariances are taken from `template_components`.
std::vector<SedsComponent> unpack_seds(const Eigen::VectorXd& params, SedsObjective objective,
                                       double covariance_floor,
                                       const std::vector<SedsComponent>& template_components);

/// Objective value at `params`; if `gradient` is non-null it receives the analytic gradient.
/// For kMse, `template_components` supplies the (unused) velocity covariances' count only.
double seds_objective(const Eigen::VectorXd& params, const SedsData& data, SedsObjective objective,
                      double covariance_floor,
                      const std::vector<SedsComponent>& template_components,
                      Eigen::VectorXd* gradient);

/// GMR of a SEDS model at y (allocation-free, log-sum-exp weights): f(y) = sum_k h_k(y) A_k y.
/// For tests and reporting; the hitting DS evaluates the equivalent joint GMM through mg::stats.
Eigen::Vector3d seds_velocity(const std::vector<SedsComponent>& components,
                              const Eigen::Vector3d& y);

/// Initial feasible guess: k-means + EM over (y, ydot) (mg::stats::fit_gmm), then each A_k is
/// projected onto the constraint set (symmetric part's eigenvalues clamped to <= -delta).
std::vector<SedsComponent> seds_initial_guess(const SedsData& data, const SedsOptions& options);

/// Drops the components whose prior is below `min_prior` (they carry no data; their parameters
/// are whatever the optimiser left there) and renormalises; keeps at least the largest one.
/// Appends one line per dropped component to `result.notes`.
void drop_empty_components(SedsResult& result, double min_prior);

/// Full fit: initial guess, NLopt SLSQP with analytic gradients, then a hard re-check of the
/// constraints (NumericalError if any `lambda_max(A_k + A_k^T) > -margin`).
SedsResult fit_seds(const SedsData& data, const SedsOptions& options);

/// The joint 6-D GMM over (y, ydot) equivalent to the components (see file comment).
stats::Gmm seds_to_gmm(const std::vector<SedsComponent>& components);
/// Back to conditional form; A_k = Sigma_ydot,y Sigma_y^-1. Does not check stability.
std::vector<SedsComponent> seds_from_gmm(const stats::Gmm& gmm);

/// Stability check of a joint GMM in the target frame: returns max_k lambda_max(A_k + A_k^T) and
/// writes max_k |b_k| / (1 + |mu_ydot_k|) into `*bias` if non-null.
double seds_check(const stats::Gmm& gmm, double* bias = nullptr);

}  // namespace mg::ds
