#pragma once
/// Field surfaces: the height z(x, y) of the lane [m] as a sum of analytic terms and heightmaps.
///
/// All terms are evaluated in the world frame: x along the lane (the default hitting direction),
/// y to the left, z up. A surface is an immutable value; `height` and `gradient` are pure.
#include <array>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace mg::field {

/// z = offset + slope_x * x + slope_y * y  (slopes are dz/dx, dz/dy, not angles).
struct PlaneTerm {
  double offset = 0.0;   ///< [m]
  double slope_x = 0.0;  ///< [-]
  double slope_y = 0.0;  ///< [-]
};

/// A Gaussian bump (negative height: a dip): z = height exp(-1/2 ((x-cx)^2/sx^2 + (y-cy)^2/sy^2)).
struct BumpTerm {
  std::array<double, 2> center{0.0, 0.0};  ///< [m]
  double height = 0.0;                     ///< [m]
  std::array<double, 2> sigma{0.1, 0.1};   ///< [m] widths along x and y
};

/// A ridge across the lane with a smooth cosine profile along `direction`:
/// z = height * (1 + cos(pi u / half_width)) / 2 for |u| < half_width, else 0, where u is the
/// signed distance from the crest line through `crest` (perpendicular to `direction`).
struct HillTerm {
  std::array<double, 2> crest{0.0, 0.0};      ///< [m] a point on the crest line
  std::array<double, 2> direction{1.0, 0.0};  ///< across the crest (normalised on load)
  double height = 0.0;                        ///< [m]
  double half_width = 0.3;                    ///< [m] from crest to foot
};

/// z = amplitude * atan(scale_x (x - cx)) * atan(scale_y (y - cy)): a saddle-like arctan surface.
/// With scale_y = 0 the y factor is replaced by 1 (a 1-D arctan step along x).
struct ArctanTerm {
  std::array<double, 2> center{0.0, 0.0};  ///< [m]
  double amplitude = 0.0;                  ///< [m]
  double scale_x = 1.0;                    ///< [1/m]
  double scale_y = 0.0;                    ///< [1/m]
};

/// A grid of heights [m] over the rectangle `bounds`, bilinearly interpolated, clamped outside.
struct HeightmapTerm {
  std::string source;                        ///< file it came from (for messages)
  std::array<double, 4> bounds{0, 1, 0, 1};  ///< [x_min, x_max, y_min, y_max] [m]
  int rows = 0;                              ///< along y
  int cols = 0;                              ///< along x
  std::vector<double> heights;               ///< rows*cols, row-major, row 0 at y_min [m]
};

/// A level pad (e.g. the tee): levels the sum of the terms *before* it to that sum's height at
/// `center`, z_c. With w(r) = 1 for r <= radius, a cubic smoothstep falling to 0 at
/// `blend_radius`, and r the distance from `center`:  z' = z + w(r) (z_c - z), so
/// grad z' = (1 - w) grad z + (z_c - z) grad w. C1 wherever the terms before it are C1. Terms
/// after it are added unchanged.
struct FlattenTerm {
  std::array<double, 2> center{0.0, 0.0};  ///< [m] (in field files: default the tee)
  double radius = 0.03;                    ///< [m] exactly level inside
  double blend_radius = 0.1;               ///< [m] unchanged surface outside (> radius)
};

/// The pad's weight w(r) and dw/dr: 1 inside `radius`, a cubic smoothstep down to 0 at
/// `blend_radius` (C1: w' = 0 at both ends).
void pad_weight(const FlattenTerm& t, double r, double& w, double& dw_dr);

using SurfaceTerm =
    std::variant<PlaneTerm, BumpTerm, HillTerm, ArctanTerm, HeightmapTerm, FlattenTerm>;

/// The lane surface: the sum of its terms (a `FlattenTerm` levels the partial sum before it).
struct Surface {
  std::vector<SurfaceTerm> terms;

  /// Height at (x, y) [m].
  double height(double x, double y) const;
  /// (dz/dx, dz/dy) at (x, y), analytic.
  std::array<double, 2> gradient(double x, double y) const;

 private:
  /// Height and gradient of the first `n` terms at (x, y).
  void evaluate(std::size_t n, double x, double y, double& z, std::array<double, 2>& g) const;
  double partial_height(std::size_t n, double x, double y) const;
};

/// Loads a heightmap grid from a CSV file (rows of heights in metres, first row at y_min, no
/// header) or a PNG image (grey levels scaled linearly to [z_min, z_max], top image row at
/// y_max). Throws `InputError`/`IoError` naming the file.
HeightmapTerm load_heightmap(const std::string& path, std::array<double, 4> bounds, double z_min,
                             double z_max);

}  // namespace mg::field
