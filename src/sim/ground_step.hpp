#pragma once
/// One 1 ms step of the ball on the ground in closed form (the planning path's core,
/// sim/fast_putt.hpp): the lane surface compiled into one pass, and MuJoCo 2.2.2's soft contact
/// for the one ball-plane pair, World::step's rolling resistance and MuJoCo's Euler step.
/// See docs/physics.md, "The planning path".
#include <array>

#include "field/surface.hpp"
#include "sim/world.hpp"

namespace mg::sim::ground {

using Vec3 = std::array<double, 3>;

constexpr int kMaxTerms = 16;

struct CompiledSurface {
  const field::Surface* generic = nullptr;  ///< heightmaps or many terms: the field's own code
  int count = 0;
  std::array<const field::SurfaceTerm*, kMaxTerms> terms{};
  std::array<double, kMaxTerms> pad_height{};  ///< FlattenTerm: height of the terms before it [m]
};

struct GroundModel {
  double radius = 0.0;                      ///< [m]
  double mass = 0.0;                        ///< [kg]
  double inertia = 0.0;                     ///< [kg m^2] (a sphere: the same about every axis)
  double timestep = 0.0;                    ///< [s]
  std::array<double, 3> gravity{};          ///< [m/s^2]
  double friction = 0.0;                    ///< sliding friction of the pair [-]
  double impratio = 1.0;                    ///< friction-to-normal impedance ratio [-]
  double mu = 0.0;                          ///< friction of MuJoCo's regularised cone [-]
  double stiffness = 0.0;                   ///< solref's K [1/s^2] (efc_KBIP[0])
  double damping = 0.0;                     ///< solref's B [1/s] (efc_KBIP[1])
  std::array<double, 5> solimp{};           ///< impedance as a function of penetration
  double imp_below = 0.0, imp_above = 0.0;  ///< solimp's sigmoid scales below/above its midpoint
  double diag = 0.0;        ///< MuJoCo's approximate inverse mass of the normal row [1/kg]
  double rho = 0.0;         ///< Penner's rolling resistance [-]
  double slip_limit = 0.0;  ///< WorldOptions::rolling_slip_limit [m/s]
  double smoothing = 0.0;   ///< WorldOptions::resistance_smoothing [rad/s]
};

/// The ball's state between steps (world frame).
struct Ball {
  Vec3 c{};             ///< centre [m]
  Vec3 v{};             ///< [m/s]
  Vec3 w{};             ///< angular velocity [rad/s]
  Vec3 a{}, alpha{};    ///< last accelerations [m/s^2], [rad/s^2] (MuJoCo's warm start)
  double normal = 0.0;  ///< last ground normal force [N] (World::step's rolling resistance)
};

/// What a closed-form step found.
enum class GroundStep {
  kTouching,  ///< stepped, the ball pressed on the ground
  kInAir,     ///< stepped, no ground contact
  kTooDeep,   ///< not stepped: the centre sank into the ground box, which MuJoCo resolves
};

/// The surface's terms compiled (at most kMaxTerms analytic ones; otherwise the field's code).
CompiledSurface compile_surface(const field::Surface& surface);
/// True when the closed form describes `world`'s ball-ground contact (see fast_putt_applies).
bool model_fits(const World& world);
/// The contact's constants read off `world`'s model.
GroundModel ground_model(const World& world);

// The ground is a box 2 cm thick: it acts as a plane only while the centre is above its top face.
// Deeper (a ball landing from a high hop) MuJoCo pushes the ball out of another face.
inline constexpr double kMaxPenetration = 0.5;  // [ball radii]

/// One timestep of the ball touching nothing but the ground: World::step (ground under the ball,
/// rolling resistance from the last normal force) and MuJoCo's step (contact, Euler).
GroundStep ground_step(const GroundModel& gm, const CompiledSurface& s, Ball& b);

}  // namespace mg::sim::ground
