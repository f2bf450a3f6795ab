#pragma once
/// Hitting-parameter learners (thesis 3.3): xi -> (theta, v) by GPR (one GP per output), GMR
/// (one GMM per output over (xi, output)) or joint GMR (one GMM over (xi, all outputs)).
///
/// GMM-based models work on standardised data (each column: (value - mean) / std, std 1 for a
/// constant column), so `reg_covar` is scale-free; the GPs standardise their output themselves.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "learning/dataset.hpp"
#include "stats/gmm.hpp"
#include "stats/gpr.hpp"

namespace mg::learning {

enum class Method { kGpr, kGmr, kJointGmr };

/// "gpr", "gmr", "joint-gmr".
std::string_view method_name(Method m);
/// Inverse of `method_name`; throws `mg::InputError` listing the choices.
Method parse_method(std::string_view name);

/// How the number of Gaussians is chosen when `TrainOptions::num_gaussians` is 0.
enum class ComponentSelection { kBic, kCrossValidation };
std::string_view selection_name(ComponentSelection s);
ComponentSelection parse_selection(std::string_view name);  ///< "bic" | "cv"

struct TrainOptions {
  Method method = Method::kGpr;
  int num_gaussians = 0;  ///< K >= 1, or 0 to choose K in 1..max_gaussians
  ComponentSelection selection = ComponentSelection::kBic;
  int max_gaussians = 5;   ///< upper end of the search (>= 1)
  int cv_folds = 5;        ///< folds for cross-validation (>= 2; capped at N)
  int restarts = 10;       ///< GPR optimiser starts and k-means++ seedings (>= 1)
  std::uint64_t seed = 1;  ///< everything random derives from it
  stats::EmOptions em{300, 1e-8, 1e-2,
                      5};  ///< reg_covar in standardised units (used as is when !choose_reg_covar)
  /// Choose reg_covar from the data instead of using em.reg_covar: no single value suits both
  /// noisy data (1e-2 is best at a few noisy points) and clean data (1e-2 over-smooths it 4x).
  /// The default is reg_covar_rows / N (at most em.reg_covar); a value of `reg_covar_grid` replaces
  /// it when its cross-validated GMR error (cv_folds folds, the same for every value) is
  /// measurably lower.
  bool choose_reg_covar = true;
  double reg_covar_rows = 0.05;  ///< > 0; 1e-3 at 50 rows, 1e-2 up to 5 rows
  std::vector<double> reg_covar_grid{1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1};
  /// GPR initial guesses and bounds (data units): empty = defaults; one entry = all outputs;
  /// else one per output. Their `restarts` is overridden by `restarts` above.
  std::vector<stats::GprOptions> gpr;
  void validate() const;  ///< throws `mg::InputError` naming the field
};

/// Per-output summary of a fit, in data units.
struct FitReport {
  // GPR
  Eigen::VectorXd length_scales;  ///< input units
  double signal_std = 0.0;
  double noise_std = 0.0;
  double log_marginal_likelihood = 0.0;
  // GMM-based
  int n_gaussians = 0;
  double reg_covar = 0.0;       ///< the covariance regularisation used (standardised units)
  double log_likelihood = 0.0;  ///< of the training data under the GMM (data units) [nats]
  double bic = 0.0;
};

/// Column standardisation z = (x - mean) / scale.
struct Standardizer {
  Eigen::VectorXd mean;   ///< (D)
  Eigen::VectorXd scale;  ///< (D), > 0
};

/// A trained learner. Immutable value type; save/load with `save_model`/`load_model`.
struct Model {
  Method method = Method::kGpr;
  std::vector<std::string> input_names;
  std::vector<std::string> output_names;
  std::uint64_t seed = 0;            ///< the seed it was trained with (recorded)
  std::vector<stats::GpModel> gps;   ///< GPR: one per output
  Standardizer input_standardizer;   ///< GMM-based
  Standardizer output_standardizer;  ///< GMM-based
  std::vector<stats::Gmm>
      gmms;  ///< GMR: one per output over (inputs, output); joint: one over (inputs, outputs)
  std::vector<FitReport> reports;  ///< (O)
  /// Quantities that were constant in the training data and are not learned, by name (e.g. the
  /// club speed "speed" [m/s] of an angle-only data set, thesis 6.2.1): who plays the model uses
  /// them as they are. File key "fixed" (optional).
  std::vector<std::pair<std::string, double>> fixed;
  /// A residual model over a prior (adaptation, docs/reality.md): when set, this model's GPs learn
  /// the correction to `prior`, with the same outputs and inputs that include every one of the
  /// prior's (the prior reads its own columns by name: a residual may add the ball's position to
  /// a prior of xi); a prediction is the prior's plus this model's, its std the root of their
  /// squares summed. File key "prior" (optional, a whole learner model; at most kMaxPriorDepth
  /// deep).
  std::shared_ptr<const Model> prior;
  /// The fixed value `name`, or nullptr.
  const double* fixed_value(std::string_view name) const {
    for (const auto& [n, v] : fixed)
      if (n == name) return &v;
    return nullptr;
  }
  int num_inputs() const { return static_cast<int>(input_names.size()); }
  int num_outputs() const { return static_cast<int>(output_names.size()); }
};

/// Predictive means and standard deviations of the outputs (data units), each (N x O). The std
/// is that of an observation (it includes the noise).
struct Predictions {
  Eigen::MatrixXd mean;
  Eigen::MatrixXd std;
};

/// GPR training rows at most: the fit costs O(N^3) per optimiser step and start (about a minute
/// at 1000 rows with 10 starts on one core), so larger sets are refused with that message
/// rather than left to run for minutes; GMR has no such bound (linear in N).
inline constexpr int kMaxGprRows = 1000;
/// Optimiser starts / k-means++ seedings at most (each costs a whole fit; 1000 is minutes).
inline constexpr int kMaxRestarts = 1000;
/// A training column whose standard deviation is at most this fraction of its largest magnitude
/// is rounding noise: it is standardised as a constant column (scale 1).
inline constexpr double kNegligibleSpread = 1e-9;
/// GMR predictions farther than this many training-output standard deviations from the training
/// mean are flagged (`beyond_training`): linear extrapolation, not a putt.
inline constexpr double kMaxPredictionSpread = 50.0;
/// Residual models over residual models (adapting an adapted model) nest at most this deep.
inline constexpr int kMaxPriorDepth = 8;

Model train(const Dataset& data, const TrainOptions& options);

/// A prediction far outside the training outputs: row, output, distance in training stds.
struct BeyondTraining {
  int row = 0;
  int output = 0;
  double spread = 0.0;
};
/// The GMR predictions of `p` farther than kMaxPredictionSpread training stds from the training
/// mean (GMR extrapolates linearly; GPR reverts to its mean, so none for GPR models).
std::vector<BeyondTraining> beyond_training(const Model& m, const Predictions& p);

/// `queries` is (N x I) in the model's input order.
Predictions predict(const Model& model, const Eigen::MatrixXd& queries);

struct Score {
  double mse = 0.0;   ///< mean square error (thesis Definition 6.1), output units^2
  double nlpd = 0.0;  ///< mean negative log predictive density [nats]
};
/// Scores per output (O) on a dataset with the model's columns.
std::vector<Score> score(const Model& model, const Dataset& validation);

/// Model file: JSON with "format": "minigolf-learner" and "format_version": 1.
inline constexpr int kModelFormatVersion = 1;
nlohmann::json model_to_json(const Model& model);
Model model_from_json(const nlohmann::json& j, std::string_view where = "model");
void save_model(const Model& model, const std::filesystem::path& path);  ///< atomic write
Model load_model(const std::filesystem::path& path);

/// Per-output fit report as JSON: {"<output>": {...}, ...} (GPR: length_scales, signal_std,
/// noise_std, log_marginal_likelihood; GMM: n_gaussians, log_likelihood, bic).
nlohmann::json report_to_json(const Model& model);

}  // namespace mg::learning
