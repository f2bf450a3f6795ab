#pragma once
/// What the fitted green leaves out (docs/belief.md, "Beyond the plant's keys").
///
/// The belief's green is one rolling resistance and one tilt over the surveyed surface. A real
/// green is not: its grass and its ground vary from place to place. What the model cannot
/// express stays in the fit's residuals, and it shows there as structure where vision error is
/// white: residuals that persist from one sample to the next (a lag-1 autocorrelation near 1
/// rather than near 0) and that agree between paths crossing the same stretch of lane.
#include <vector>

#include "belief/path_fit.hpp"

namespace mg::belief {

/// The residuals over one stretch of the lane along x.
struct ResidualBin {
  double x_from = 0.0, x_to = 0.0;  ///< [m]
  int samples = 0;
  int paths = 0;        ///< distinct paths with samples here
  double along = 0.0;   ///< [m] mean residual along the model ball's motion (+: ahead of it)
  double across = 0.0;  ///< [m] mean residual across it (+: to its left)
  double rms = 0.0;     ///< [m] per axis
};

struct ResidualSummary {
  int samples = 0;
  double rms_along = 0.0;   ///< [m]
  double rms_across = 0.0;  ///< [m]
  /// Lag-1 autocorrelation of the residual vectors within each rolling run, pooled: about 0
  /// (within a few 1/sqrt(samples)) for white vision error, near 1 when the model misses
  /// something smooth.
  double lag1 = 0.0;
  /// lag1 above kStructuredLag1 and above 4/sqrt(samples): the residual is the model's, not
  /// the camera's.
  bool structured = false;
  std::vector<ResidualBin> bins;  ///< along x, `bin_width` wide, empty bins left out
};

/// The lag-1 autocorrelation above which a residual counts as structured.
inline constexpr double kStructuredLag1 = 0.3;

/// Summarises `estimate.residuals` (fit_green's) in bins of `bin_width` [m] along x. Throws
/// InputError for a bin width that is not positive and finite.
ResidualSummary summarize_residuals(const GreenEstimate& estimate, double bin_width = 0.25);

}  // namespace mg::belief
