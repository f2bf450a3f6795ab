#pragma once
/// The hitting model: everything the hitting DS needs, immutable and validated once.
///
/// - SEDS GMM over (y, ydot), y = x - x* (target frame, default hitting direction psi0): the
///   target field E(y) = f(y)/|f(y)| with f the GMR of ydot on y.
/// - Strength GMM over (y, |ydot|): v(y) by GMR (EM fit, no constraints).
/// - x* [m, world], psi0 (unit, horizontal, world), the default hitting speed v(x*) [m/s].
/// - The guidance settings near the ball (see HittingDsSettings).
///
/// File: JSON, `format_version` 1 (see notes/ds.md); read_hitting_model rejects anything else.
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "ds/demonstrations.hpp"
#include "ds/seds.hpp"
#include "stats/gmm.hpp"
#include "stats/gmr.hpp"

namespace mg::ds {

inline constexpr int kHittingModelFormatVersion = 1;

/// Shape of the DS near the ball (stored in the model file; defaults in one place).
///
/// Why: SEDS alone reaches x* from whatever direction its GMM implies (the slowest eigen-direction
/// of sum_k h_k(0) A_k), not necessarily along psi0. Inside a ball of radius `blend_outer` around
/// x*, and only for points behind the ball (inside a cone about -psi0), the direction is blended
/// smoothly toward a line-guidance field E_l = normalise(psi0 - n y_perp / |y_par|) (y_par, y_perp:
/// components of y along and across psi0). Along E_l the lateral offset shrinks like |y_par|^n, so
/// the path reaches x* exactly, tangent to psi0. Both fields have E . y < 0, so every blend does
/// too: |x - x*| still decreases everywhere (the SEDS Lyapunov argument survives the blend).
struct HittingDsSettings {
  double blend_inner = 0.10;           ///< [m] pure line guidance inside this radius
  double blend_outer = 0.25;           ///< [m] pure SEDS field outside this radius
  double cone_cos_min = 0.0;           ///< no guidance if cos(angle(x* - x, psi0)) below this
  double cone_cos_max = 0.15;          ///< full guidance above this
  double line_exponent = 3.0;          ///< n > 1: lateral offset ~ |y_par|^n
  double min_strength_fraction = 0.1;  ///< v(x) floor, fraction of v(x*) (GMR from rest is ~0)
  double max_strength_fraction = 2.0;  ///< v(x) cap, fraction of v(x*) (GMR extrapolates linearly)
  void validate() const;               ///< throws InputError naming the field
};

class HittingModel {
 public:
  /// Validates everything; throws InputError on malformed parts and NumericalError if the SEDS
  /// GMM violates the stability conditions (lambda_max(A_k + A_k^T) <= -margin, b_k = 0).
  HittingModel(stats::Gmm seds_gmm, stats::Gmm strength_gmm, const Eigen::Vector3d& x_star,
               const Eigen::Vector3d& psi0, const HittingDsSettings& settings,
               double margin = 1e-4);

  const stats::Gmm& seds_gmm() const { return seds_gmm_; }          ///< (y, ydot), target frame
  const stats::Gmm& strength_gmm() const { return strength_gmm_; }  ///< (y, |ydot|), target frame
  const Eigen::Vector3d& x_star() const { return x_star_; }         ///< [m], world
  const Eigen::Vector3d& psi0() const { return psi0_; }             ///< unit, world, horizontal
  double default_speed() const { return default_speed_; }           ///< v(x*) [m/s]
  const HittingDsSettings& settings() const { return settings_; }
  double max_eigenvalue() const {
    return max_eigenvalue_;
  }  ///< max_k lambda_max(A_k + A_k^T) [1/s]
  const stats::GmrConditioner& seds_gmr() const { return seds_gmr_; }
  const stats::GmrConditioner& strength_gmr() const { return strength_gmr_; }

  /// Free-form provenance stored in the file (fit options, seed, objective, numbers).
  nlohmann::json provenance = nlohmann::json::object();

 private:
  stats::Gmm seds_gmm_;
  stats::Gmm strength_gmm_;
  Eigen::Vector3d x_star_;
  Eigen::Vector3d psi0_;
  HittingDsSettings settings_;
  stats::GmrConditioner seds_gmr_;
  stats::GmrConditioner strength_gmr_;
  double default_speed_ = 0.0;
  double max_eigenvalue_ = 0.0;
};

struct HittingFitOptions {
  SedsOptions seds;
  int strength_gaussians = 0;  ///< 0: same as seds.gaussians
  double min_speed_fraction =
      0.05;                     ///< samples slower than this x hitting speed are left out of SEDS
  double end_tolerance = 0.02;  ///< [m] demonstrations must end within this of a common x*
  HittingDsSettings settings;
};

struct HittingFitReport {
  SedsResult seds;
  int samples_used = 0;      ///< samples in the SEDS fit
  double fit_seconds = 0.0;  ///< wall time of the whole fit
  /// What the fit did on its own to succeed (fewer Gaussians, components dropped), one line each.
  std::vector<std::string> notes;
  DemoSummary summary;
};

/// SEDS + strength GMM fit on demonstrations (world frame). Throws InputError on unusable
/// demonstrations, NumericalError if the fitted constraints do not hold.
HittingModel fit_hitting_model(const std::vector<Demonstration>& demos,
                               const HittingFitOptions& options,
                               HittingFitReport* report = nullptr);

nlohmann::json hitting_model_to_json(const HittingModel& model);
/// Throws InputError naming `source` and the field on a wrong format_version, missing or
/// malformed fields, or violated stability constraints.
HittingModel hitting_model_from_json(const nlohmann::json& j, const std::string& source = "model");
void write_hitting_model(const std::filesystem::path& path, const HittingModel& model);
HittingModel read_hitting_model(const std::filesystem::path& path);

}  // namespace mg::ds
