#pragma once
/// What the learners share inside src/learning (not a public interface): column standardisation
/// and the choice of a GMM-based model's number of Gaussians and covariance regularisation
/// (model_selection.cpp), used by train() and predict() (learner.cpp).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "learning/learner.hpp"
#include "stats/gmm.hpp"

namespace mg::learning::detail {

/// Column means and scales of `m` (a column of rounding-noise spread gets scale 1).
Standardizer make_standardizer(const Eigen::MatrixXd& m);
/// (m - mean) / scale, column by column.
Eigen::MatrixXd apply(const Standardizer& s, const Eigen::MatrixXd& m);
/// first, first + 1, ..., first + count - 1.
std::vector<int> iota_dims(int first, int count);

/// A fitted GMM over (standardised inputs, outputs) and the reg_covar it was fitted with.
struct GmmFit {
  stats::EmResult em;
  double reg_covar = 0.0;
};
/// Fits the GMM of a GMR or joint-GMR learner to `joint` ((N x (I + O)), standardised, inputs
/// first): K = opt.num_gaussians, or chosen by BIC or cross-validation; reg_covar chosen as
/// TrainOptions says. Throws InputError for more Gaussians than rows.
GmmFit fit_gmm_model(const Eigen::MatrixXd& joint, int num_inputs, const TrainOptions& opt,
                     std::uint64_t seed);

}  // namespace mg::learning::detail
