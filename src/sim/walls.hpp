#pragma once
/// The lane's borders and obstacles as the ball meets them, and the impact as an impulse.
///
/// MuJoCo 2.2.2 has no coefficient of restitution: a bounce from a soft contact (solref's
/// damping ratio) returned more energy than it took above about 2.5 m/s, and the wall's friction
/// on a rolling ball's forward spin lifted it off the lane (docs/physics.md, "Borders and
/// walls"). The walls are therefore drawn by MuJoCo but collided here, after each step, as rigid
/// vertical prisms:
///
/// - normal: the speed into the face leaves at `restitution` times itself (Newton's law);
/// - friction at the contact point (Coulomb, `kWallFriction`), at most until the point sticks;
///   on a vertical face it slows the ball along the face (side spin never speeds it up) and the
///   spin's slip across it, but gives no vertical speed: the ball meets a face at its equator,
///   and the border is taken as a cushion whose nose cancels the lift (the billiard cushion's
///   design; Mathavan, Jackson and Parkin 2010), so no impact launches the ball;
/// - the ball's centre is put where the bounce would have taken it during the step (mirrored
///   off the face's plane by the restitution), at the same height above the ground.
///
/// Every impact keeps or lowers the kinetic energy (tests/sim/test_walls.cpp checks it over
/// 10,000 random putts). Real-time safe: no allocation, no exceptions.
#include <array>

#include "field/field.hpp"

namespace mg::sim {

/// Coulomb friction of the ball against a border or obstacle face [-].
inline constexpr double kWallFriction = 0.2;

/// A vertical prism over an oriented rectangle (a border or an obstacle).
struct WallPrism {
  double cx = 0.0, cy = 0.0;            ///< footprint centre [m]
  double hx = 0.0, hy = 0.0;            ///< half lengths along its own x and y [m]
  double cos_yaw = 1.0, sin_yaw = 0.0;  ///< its own x axis in the world
  double bottom = 0.0, top = 0.0;       ///< [m]
  double restitution = 0.0;             ///< [-]
};

/// Every border (4) and obstacle of a field, with the ball they bounce.
struct Walls {
  int count = 0;
  std::array<WallPrism, 4 + field::kMaxObstacles> prisms{};
  double radius = 0.0;          ///< ball [m]
  double inertia_ratio = 0.4;   ///< I / (m r^2) of the ball [-] (a solid sphere)
  double sample_spacing = 0.0;  ///< [m] the swept path is checked this often (no tunnelling)
};

/// The field's borders (boxes `borders.thickness` wide outside `bounds`, as the MJCF draws them)
/// and obstacles.
Walls make_walls(const field::Field& field);

/// What resolve_walls did.
struct WallImpact {
  double normal_speed = 0.0;  ///< [m/s] fastest speed into a face (0: no impact)
  int prism = -1;             ///< its index in Walls::prisms (-1: none)
};

/// The impact of a ball on a face with unit normal `n` (out of the face), per walls.hpp: changes
/// the velocity `v` [m/s] and the angular velocity `w` [rad/s] (world frame) of a ball of radius
/// `radius` [m] and I / (m r^2) = `inertia_ratio`. Returns the speed into the face (0: the ball
/// leaves it, nothing changed).
double wall_impulse(const std::array<double, 3>& n, double restitution, double radius,
                    double inertia_ratio, std::array<double, 3>& v, std::array<double, 3>& w);

/// How a ball rolling into a vertical face at `incidence` [rad from the face's normal] rolls away
/// once the slide after the impact is over, on level ground.
struct RollingRebound {
  double speed = 0.0;  ///< rolling speed after / before [-]
  double angle = 0.0;  ///< [rad] from the face's normal (pi/2: along the face)
};
RollingRebound rolling_rebound(double restitution, double incidence, double inertia_ratio = 0.4);

/// Resolves the ball's contacts with the walls after a step that moved its centre from
/// `previous` to `c` [m]: velocity `v` [m/s] and angular velocity `w` [rad/s], world frame.
/// Changes c, v and w in place; the height above the surface of `field` is kept when the centre
/// is moved. At most four contacts (a corner) per call.
WallImpact resolve_walls(const Walls& walls, const field::Field& field,
                         const std::array<double, 3>& previous, std::array<double, 3>& c,
                         std::array<double, 3>& v, std::array<double, 3>& w);

/// [m] distance from `c` to the nearest wall prism minus the ball radius (<= 0: touching).
double wall_clearance(const Walls& walls, const std::array<double, 3>& c);

}  // namespace mg::sim
