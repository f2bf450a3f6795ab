#pragma once
/// The robot's putt planner: a prior plus a residual learned from its own putts.
///
/// The prior is either what a person would use (aim at the hole, Penner's rolling distance,
/// mapped to the club by the launch relation measured on the robot's own putts: self-teaching
/// from scratch), or a learner model learned elsewhere, in the nominal simulator say (adaptation:
/// `self-teach --prior`, `evaluate --learn`). A GP per output on (label - prior) at the hindsight
/// labels corrects it; putts whose path labels nothing near their target add a planning-only
/// pseudo-label (the putt corrected by how it missed, as the teacher's first Newton step).
///
/// With a model prior the residual GP's hyperparameters are fixed (kResidualLabelsToTune labels
/// and fewer) to what a plant's error looks like: a smooth correction over the region (length
/// scales: the region's extent), 10 mrad and 0.05 m/s in size, label noise 1.5 mrad and 0.01 m/s;
/// its mean is the labels' mean residual, so one putt already corrects the whole region. Beyond
/// that they maximise the marginal likelihood, length scales no shorter than a quarter of the
/// extent. A fit of a few points by marginal likelihood is noise (measured: docs/reality.md).
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/rng.hpp"
#include "field/situations.hpp"
#include "learning/learner.hpp"
#include "selfteach/hindsight.hpp"
#include "stats/gpr.hpp"
#include "system/system.hpp"

namespace mg::selfteach {

struct PuttRecord;

/// [rad], [m/s] the sinking window's scale (teacher margins): the planner's uncertainty unit.
inline constexpr double kWindowAngle = 0.004;
inline constexpr double kWindowSpeed = 0.03;
/// With a model prior: labels up to this count use the fixed residual hyperparameters.
inline constexpr int kResidualLabelsToTune = 15;

/// The model's inputs at `situation` (field::situation_input of each name).
Eigen::VectorXd input_row(const field::Field& field, const std::vector<std::string>& inputs,
                          const field::Situation& situation);
/// The same with the ball on the tee.
Eigen::VectorXd input_row(const field::Field& field, const std::vector<std::string>& inputs,
                          std::array<double, 2> hole);

/// The residual GP hyperparameters for a model prior with `labels` labels on `region`, output
/// `output` (0 angle, 1 speed): the fixed ones (see the file comment), or std::nullopt when they
/// are to be fitted.
std::optional<stats::GpHyperparameters> fixed_residual_hyper(const field::Situations& region,
                                                             int inputs, int output, int labels);

class Planner {
 public:
  /// `prior`: a learner model (adaptation), or nullptr for the physical prior (self-teaching).
  /// Throws InputError if the model does not fit the region (inputs, an angle output, speed for
  /// an angle-and-speed region).
  Planner(const system::System& system, const field::Situations& region, double arrival,
          std::uint64_t seed, std::shared_ptr<const learning::Model> prior = nullptr);

  void set_arrival(double arrival) { arrival_ = arrival; }

  /// Re-estimates the launch relation from `putts` and refits the residual GPs to `labels` plus
  /// the pseudo-labels of the putts that gave none near their target.
  void update(const std::vector<PuttRecord>& putts, std::vector<Label> labels);

  /// The putt `p` corrected by how it missed its target (the teacher's first Newton step).
  Label pseudo_label(const PuttRecord& p, int index) const;

  /// The prior's club (angle, speed) for a situation.
  std::array<double, 2> prior(const field::Situation& situation) const;

  /// The putt for a situation, inside the module's envelope, and its uncertainty in window units.
  std::array<double, 3> plan(const field::Situation& situation) const;
  /// The same with the ball on the tee.
  std::array<double, 3> plan(std::array<double, 2> hole) const;
  /// `plan` for a putt the robot is about to play: with a model prior on an angle-only region in
  /// a belief, the club speed is chosen for the planned angle in the believed ball world
  /// (system::believed_club_speed; about 0.1 s, so not for every candidate); else `plan` itself.
  std::array<double, 3> plan_to_play(const field::Situation& situation) const;

  /// The residual model over the prior model from what the robot knows for sure after its first
  /// `putts` putts (all for a negative value): the hindsight `labels` and its putts that sank
  /// (each a label at its own target, where no hindsight label lies within 2 cm), not the
  /// planning-only pseudo-labels; with this planner's hyperparameter policy. The prior itself
  /// while there is none. Needs a model prior; throws InputError otherwise.
  learning::Model residual_model(const std::vector<Label>& labels, int putts) const;

  bool has_model_prior() const { return prior_model_ != nullptr; }
  const std::vector<std::string>& inputs() const { return inputs_; }

 private:
  /// The residual GPs' hyperparameters for `labels` rows (fitted, or fixed with a model prior).
  std::vector<stats::GpHyperparameters> hyperparameters(const Eigen::MatrixXd& x,
                                                        const Eigen::MatrixXd& r);

  const system::System& sys_;
  const field::Situations& region_;
  std::vector<std::string> inputs_;
  double arrival_;
  Rng rng_;
  std::shared_ptr<const learning::Model> prior_model_;
  int outputs_ = 1;
  double bias_ = 0.0, ratio_ = 1.6;
  std::vector<stats::GpHyperparameters> hyper_;
  Eigen::Index fitted_at_ = 0;
  std::vector<stats::GpModel> gps_;
  std::vector<Label> sunk_;  ///< the putts that sank, as labels at their targets (last update)
};

}  // namespace mg::selfteach
