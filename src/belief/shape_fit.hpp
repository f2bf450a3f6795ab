#pragma once
/// A spatial correction of the green (docs/belief.md, "Beyond the plant's keys"): where one
/// rolling resistance and one tilt leave a structured residual, the lane's shape is corrected by
/// a grid of Gaussian bumps whose heights are fitted to the same paths. The result is a list of
/// bumps in the plant file's own key (`field.bumps`), so a belief carries it to every planner.
///
/// The fit alternates two blocks: the green (fit_green: rho, the tilt and each path's start, on
/// the lane with the current bumps) and the bumps' heights (one Gauss-Newton step with the green
/// held, a Gaussian prior of `height_std` on each height: a bump no path crosses stays at 0).
#include <vector>

#include "belief/path_fit.hpp"
#include "field/surface.hpp"

namespace mg::belief {

struct ShapeOptions {
  /// [m] between the grid's bumps (the finest: coarsened by 1.25 until the bumps a path crosses
  /// fit the plant file's limit, plant::kMaxPlantBumps)
  double spacing = 0.5;
  double sigma_ratio = 0.8;   ///< each bump's width over the spacing
  double height_std = 0.001;  ///< [m] the prior std of each height
  int rounds = 3;             ///< green and heights, alternated
};

struct ShapeEstimate {
  std::vector<field::BumpTerm> bumps;  ///< the grid's bumps crossed by a path, heights fitted
  GreenEstimate green;                 ///< the green on the lane with the bumps
  double rms_before = 0.0;             ///< [m] the green fit's rms residual without the bumps
};

/// The lane `surveyed` with `bumps` added to its surface.
field::Field with_bumps(const field::Field& surveyed, const std::vector<field::BumpTerm>& bumps);

/// Fits the grid's bumps (over the lane's bounds, those within 1.5 widths of a fitted sample) and
/// the green to `paths` (first rolling runs, as fit_green(every_run = false)). Deterministic.
/// Throws InputError for options out of range (spacing 0.05-2 m, sigma ratio 0.2-3, height std
/// 0-0.05 m, rounds 1-10) and as fit_green.
ShapeEstimate fit_shape(const field::Field& surveyed, const std::vector<ObservedPath>& paths,
                        const GreenPrior& prior, const ShapeOptions& options = {});

}  // namespace mg::belief
