#pragma once
/// A minigolf lane as data: bounds, surface, tee, hole, ball, resistances, borders.
///
/// Fields are YAML files (format: docs/fields.md). A field named without a path
/// (`flat`) is the shipped one in `data/fields/`; anything with a '/' or a `.yaml`/`.yml`
/// suffix is a user's file. A `Field` is validated once, on load.
#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "field/obstacles.hpp"
#include "field/situations.hpp"
#include "field/surface.hpp"

namespace mg::field {

/// The hole: a cylindrical cup cut into the surface.
struct Hole {
  std::array<double, 2> position{2.0, 0.0};  ///< centre, world frame [m]
  double diameter = 0.108;                   ///< [m] (golf: 108 mm)
  double depth = 0.06;                       ///< [m] below the surface at the centre
};

/// The ball (default: a golf ball, 42.67 mm, 45.93 g).
struct Ball {
  double radius = 0.021335;  ///< [m]
  double mass = 0.04593;     ///< [kg]
};

/// The lane's borders (walls) around `bounds`.
struct Borders {
  double height = 0.06;      ///< [m] above the highest point of the surface next to them
  double thickness = 0.04;   ///< [m]
  double restitution = 0.6;  ///< [-] normal speed after / before a head-on bounce
};

struct Field {
  std::string name;
  std::string description;
  std::string source;                                  ///< file the field was read from
  std::array<double, 4> bounds{-0.3, 2.7, -0.6, 0.6};  ///< lane [x_min, x_max, y_min, y_max] [m]
  double cell_size = 0.025;                            ///< heightfield grid spacing [m]
  std::array<double, 2> tee{0.0, 0.0};                 ///< ball start [m]
  Hole hole;
  Ball ball;
  double rolling_resistance = 0.131;  ///< Penner's rho [-]: rolling decel (5/7) rho g
  double sliding_friction = 0.3;      ///< ball-lane Coulomb friction while sliding [-]
  Borders borders;
  std::vector<Obstacle> obstacles;  ///< walls and blocks on the lane (file section `obstacles`)
  Surface surface;
  Situations situations;  ///< where the hole may be (file section `situations`, or the default)

  /// Throws `InputError` naming the first bad value.
  void validate() const;
  /// Height of the lane at (x, y) [m].
  double height(double x, double y) const { return surface.height(x, y); }
};

/// Loads a field by shipped name or by path (see file comment). Throws `InputError`/`IoError`.
Field load_field(std::string_view name_or_path);

/// Parses field YAML text. `base_dir` resolves relative heightmap paths; `source` names the
/// text in error messages.
Field parse_field(std::string_view yaml_text, const std::string& source,
                  const std::filesystem::path& base_dir);

/// Names of the shipped fields, sorted.
std::vector<std::string> list_shipped_fields();

/// Throws `InputError` unless a hole centred at `position` lies wholly inside the lane.
void check_hole_position(const Field& field, std::array<double, 2> position);

/// Throws InputError naming `what` unless a ball at `ball` lies on the lane, a ball radius from
/// its borders and clear of every obstacle.
void check_ball_position(const Field& field, std::array<double, 2> ball, const std::string& what);

/// [m] The lowest and the highest height of the lane over its heightfield grid (cell_size
/// apart, corners included): the extent the world's ground and borders are built for.
std::array<double, 2> height_range(const Field& field);

/// [m] Height of an obstacle's top: `height` above the highest ground under its footprint
/// (sampled on a 9 x 9 grid).
double obstacle_top(const Field& field, const Obstacle& obstacle);

/// True if the segment a -> b passes within `clearance` [m] of an obstacle (sampled 1 cm apart):
/// a ball rolling straight along it would meet one.
bool line_blocked(const Field& field, std::array<double, 2> a, std::array<double, 2> b,
                  double clearance);

}  // namespace mg::field
