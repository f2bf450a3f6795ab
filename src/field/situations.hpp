#pragma once
/// Where the hole may be on a field: the region a learner must cover (thesis 2.2, 5.2).
///
/// A field file's optional `situations` section gives one of four shapes of hole positions:
///   line  {from: [x, y], to: [x, y], count: N}        N equally spaced holes, ends included
///   grid  {x: [x0, x1], y: [y0, y1], counts: [nx, ny]} nx x ny evenly spaced holes
///   box   {x: [x0, x1], y: [y0, y1], counts: [nx, ny]} the rectangle; collect on its grid
///   list  {points: [[x, y], ...]}                      exactly these holes
/// plus what is learned there: `outputs: [angle]` (angle only, at `speed`, the club speed the
/// data set is collected with: thesis 6.2.1-6.2.2) or `[angle, speed]`, and the teacher's
/// default `strategy` (min-speed | min-angle). Test situations are drawn uniformly from the line
/// segment or the rectangle, or uniformly from the list. Default (no section): a 3 x 3 grid box of
/// +-0.1 m around the field's hole, angle and speed, min-speed.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/rng.hpp"

namespace mg::field {

struct Field;

enum class RegionShape { kLine, kGrid, kBox, kList };
std::string to_string(RegionShape shape);

struct Situations {
  RegionShape shape = RegionShape::kBox;
  std::array<double, 2> from{0, 0}, to{0, 0};          ///< line ends [m]
  int count = 0;                                       ///< line: number of holes
  std::array<double, 2> x_range{0, 0}, y_range{0, 0};  ///< grid/box [m]
  std::array<int, 2> counts{0, 0};                     ///< grid/box: holes along x and y
  std::vector<std::array<double, 2>> points;           ///< list [m]
  bool learn_speed = true;  ///< outputs [angle, speed]; false: angle only at `speed`
  double speed = 0.0;       ///< [m/s] club speed of an angle-only region (0 with learn_speed)
  std::string strategy = "min-speed";  ///< the teacher's default strategy here
  bool from_file = false;              ///< false: the default region was filled in

  /// The learner inputs of the region: a line's one coordinate (xi_x or xi_y, whichever varies
  /// more), else xi_x, xi_y (hole - tee [m]); outputs angle[, speed].
  std::vector<std::string> learner_inputs() const;
  std::vector<std::string> learner_outputs() const;
  /// The hole positions a data set is collected at (line, grid and box: their grid; list: the
  /// points), in a fixed order (x-major for grids).
  std::vector<std::array<double, 2>> collection_points() const;
  /// One test situation drawn uniformly from the region.
  std::array<double, 2> sample(Rng& rng) const;
  /// `n` test situations from `seed` (sample i uses its own stream: independent of n's split).
  std::vector<std::array<double, 2>> sample(int n, std::uint64_t seed) const;
  /// Throws InputError (naming `where`, default: the field file's situations) if a hole of the
  /// region leaves the field's lane, or a count or range is unusable.
  void validate(const Field& field, const std::string& where = "") const;
  /// (x_min, x_max, y_min, y_max) [m] of every hole the region holds or samples.
  std::array<double, 4> bounds() const;
};

/// The value of a learner input for a hole on `field`: xi_x, xi_y (hole - tee), hole_x or hole_y
/// [m]. Throws InputError for another name.
double situation_input(const Field& field, std::string_view name, std::array<double, 2> hole);

/// The default region of a field without a `situations` section.
Situations default_situations(const Field& field);

/// The region from a spec given on the command line (`--situations`):
///   line:X0,Y0:X1,Y1:N | grid:X0,X1:Y0,Y1:NX,NY | box:X0,X1:Y0,Y1:NX,NY | list:X,Y;X,Y;...
/// The outputs, speed and strategy are kept from `base`. Throws InputError.
Situations parse_situations_spec(const std::string& spec, const Situations& base);

/// The field's own region (empty `spec`) or the one of `spec`, validated against the lane (the
/// `--situations` option of the CLI and the `situations` arguments of Python). InputError.
Situations region_from_spec(const Field& field, const std::string& spec);

}  // namespace mg::field
