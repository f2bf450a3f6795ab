#pragma once
/// Where the hole may be on a field: the region a learner must cover (thesis 2.2, 5.2).
///
/// A field file's optional `situations` section gives one of four shapes of hole positions:
///   line  {from: [x, y], to: [x, y], count: N}        N equally spaced holes, ends included
///   grid  {x: [x0, x1], y: [y0, y1], counts: [nx, ny]} nx x ny evenly spaced holes
///   box   {x: [x0, x1], y: [y0, y1], counts: [nx, ny]} the rectangle; collect on its grid
///   list  {points: [[x, y], ...]}                      exactly these holes
/// and, under `ball:`, optionally where the ball lies (the same four shapes; default: the tee),
/// plus what is learned there: `outputs: [angle]` (angle only, at `speed`, the club speed the
/// data set is collected with: thesis 6.2.1-6.2.2) or `[angle, speed]`, and the teacher's
/// default `strategy` (min-speed | min-angle). Test situations are drawn uniformly from the line
/// segment or the rectangle, or uniformly from the list. Default (no section): a 3 x 3 grid box of
/// +-0.1 m around the field's hole, angle and speed, min-speed.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/rng.hpp"

namespace mg::field {

struct Field;

enum class RegionShape { kLine, kGrid, kBox, kList };
std::string to_string(RegionShape shape);

/// A set of points on the lane in one of the four shapes above.
struct Region {
  RegionShape shape = RegionShape::kBox;
  std::array<double, 2> from{0, 0}, to{0, 0};          ///< line ends [m]
  int count = 0;                                       ///< line: number of points
  std::array<double, 2> x_range{0, 0}, y_range{0, 0};  ///< grid/box [m]
  std::array<int, 2> counts{0, 0};                     ///< grid/box: points along x and y
  std::vector<std::array<double, 2>> points;           ///< list [m]

  /// The points a data set is collected at (line, grid and box: their grid; list: the points),
  /// in a fixed order (x-major for grids).
  std::vector<std::array<double, 2>> collection_points() const;
  /// One point drawn uniformly from the region.
  std::array<double, 2> sample(Rng& rng) const;
  /// `n` points from `seed` (sample i uses its own stream: independent of n's split).
  std::vector<std::array<double, 2>> sample(int n, std::uint64_t seed) const;
  /// (x_min, x_max, y_min, y_max) [m] of every point the region holds or samples.
  std::array<double, 4> bounds() const;
  /// The points that bound the region: a line's ends, a rectangle's corners, a list's points.
  std::vector<std::array<double, 2>> corners() const;
  /// Throws InputError (prefixed `where`) if a count or range is unusable.
  void check_shape(const std::string& where) const;
  bool operator==(const Region&) const = default;
};

/// One situation: where the ball lies and where the hole is. (A constructor, not an aggregate,
/// so that `{x, y}` stays a hole position where both overloads exist.)
struct Situation {
  Situation() = default;
  Situation(std::array<double, 2> ball_at, std::array<double, 2> hole_at)
      : ball(ball_at), hole(hole_at) {}
  std::array<double, 2> ball{0, 0};  ///< [m]
  std::array<double, 2> hole{0, 0};  ///< [m]
  bool operator==(const Situation&) const = default;
};

/// The hole region (the Region base) and, optionally, where the ball lies (`ball:` in the file,
/// the same four shapes; default: the field's tee), with what is learned there.
struct Situations : Region {
  /// Where the ball may lie; none: on the tee. The robot stands beside the ball as it stands
  /// beside the tee, facing the same way (system::stance_for with aim 0), so hitting angles stay
  /// world angles and a flat lane's model of xi = hole - ball holds from anywhere.
  std::optional<Region> balls;
  bool learn_speed = true;  ///< outputs [angle, speed]; false: angle only at `speed`
  double speed = 0.0;       ///< [m/s] club speed of an angle-only region (0 with learn_speed)
  std::string strategy = "min-speed";  ///< the teacher's default strategy here
  bool from_file = false;              ///< false: the default region was filled in
  /// With a ball region: the learners also take the ball's position (ball_x, ball_y), because
  /// the lane is not translation-invariant (translation_invariant(field); set where the region
  /// is read).
  bool ball_inputs = false;

  /// The learner inputs of the region: without a ball region a line's one coordinate (xi_x or
  /// xi_y, whichever varies more), else xi_x, xi_y (hole - ball [m]); plus ball_x, ball_y when
  /// `ball_inputs`. Outputs angle[, speed].
  std::vector<std::string> learner_inputs() const;
  std::vector<std::string> learner_outputs() const;
  /// The situations a data set is collected at: every ball point (or the tee) with every hole
  /// point, ball-major, skipping pairs whose hole covers the ball.
  std::vector<Situation> collection_situations(const Field& field) const;
  /// `n` test situations from `seed`: situation i's hole as Region::sample(n, seed) draws it, then
  /// its ball from the same stream (redrawn while the hole covers it); without a ball region the
  /// tee, so the holes are those of a region without balls.
  std::vector<Situation> sample_situations(const Field& field, int n, std::uint64_t seed) const;
  /// One situation from `rng`: its hole (Region::sample), then its ball from the same stream
  /// (the tee without a ball region). Throws InputError if no ball clears the hole.
  Situation sample_situation(const Field& field, Rng& rng) const;
  /// Throws InputError (naming `where`, default: the field file's situations) if a hole of the
  /// region leaves the field's lane, a ball of its ball region leaves it, or a count or range is
  /// unusable.
  void validate(const Field& field, const std::string& where = "") const;
};

/// The steepest slope a ball may be placed on, as a fraction of the lane's rolling resistance rho.
/// A real ball rests where |grad z| < rho; the simulated resting ball creeps on any slope, faster
/// near rho (on arctan it rolled off at 0.144 = 1.1 rho while the arm took its rest pose), so a
/// margin is kept.
inline constexpr double kRestSlopeFraction = 0.8;

/// True if a ball can lie at rest at `p`: |grad z| <= kRestSlopeFraction * rolling_resistance.
bool ball_rests(const Field& field, std::array<double, 2> p);

/// False if the hole covers the ball (closer than a hole diameter), the ball lies in an obstacle,
/// or a ball off the tee could not rest where it lies (ball_rests): no putt to play there.
bool playable(const Field& field, const Situation& situation);

/// True if putting on `field` depends on hole - ball only (away from the borders): its surface
/// has one gradient everywhere on the lane (a plane), and it has no obstacles.
bool translation_invariant(const Field& field);

/// The names a learner input may have: what situation_input gives.
inline constexpr std::array<std::string_view, 6> kSituationInputs{"xi_x",   "xi_y",   "hole_x",
                                                                  "hole_y", "ball_x", "ball_y"};

/// The value of a learner input for a situation on `field`: xi_x, xi_y (hole - ball), hole_x,
/// hole_y, ball_x or ball_y [m]. Throws InputError for another name.
double situation_input(const Field& field, std::string_view name, const Situation& situation);
/// The same with the ball on the tee.
double situation_input(const Field& field, std::string_view name, std::array<double, 2> hole);

/// The default region of a field without a `situations` section.
Situations default_situations(const Field& field);

/// The region from a spec given on the command line (`--situations`):
///   line:X0,Y0:X1,Y1:N | grid:X0,X1:Y0,Y1:NX,NY | box:X0,X1:Y0,Y1:NX,NY | list:X,Y;X,Y;...
/// The outputs, speed and strategy are kept from `base`. Throws InputError.
Situations parse_situations_spec(const std::string& spec, const Situations& base);

/// The field's own region (empty `spec`) or the one of `spec`, validated against the lane (the
/// `--situations` option of the CLI and the `situations` arguments of Python); with `balls_spec`
/// (the same grammar, `--balls`) the balls lie in that region instead of the field's. InputError.
Situations region_from_spec(const Field& field, const std::string& spec,
                            const std::string& balls_spec = "");

}  // namespace mg::field
