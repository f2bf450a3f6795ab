#include "sim/fast_putt.hpp"

#include <algorithm>
#include <cmath>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// The lane surface, compiled: height and gradient of the analytic terms in one pass, each
// transcendental evaluated once and a pad's levelled height precomputed (field::Surface
// recomputes both per call: 4-8x slower on the hill fields). Same formulas in the same order as
// src/field/surface.cpp, so the same numbers up to an ulp.

constexpr int kMaxTerms = 16;

struct CompiledSurface {
  const field::Surface* generic = nullptr;  ///< heightmaps or many terms: the field's own code
  int count = 0;
  std::array<const field::SurfaceTerm*, kMaxTerms> terms{};
  std::array<double, kMaxTerms> pad_height{};  ///< FlattenTerm: height of the terms before it [m]
};

// As field::Surface's pad_weight: w(r) and dw/dr of a level pad.
void pad_weight(const field::FlattenTerm& t, double r, double& w, double& dw_dr) {
  if (r <= t.radius) {
    w = 1.0, dw_dr = 0.0;
  } else if (r >= t.blend_radius) {
    w = 0.0, dw_dr = 0.0;
  } else {
    const double width = t.blend_radius - t.radius, s = (r - t.radius) / width;
    w = 1.0 - s * s * (3.0 - 2.0 * s);
    dw_dr = -6.0 * s * (1.0 - s) / width;
  }
}

// Adds one analytic term's height and gradient at (x, y) to z, g.
void add_term(const field::SurfaceTerm& term, double x, double y, double& z, double* g) {
  if (const auto* t = std::get_if<field::PlaneTerm>(&term)) {
    z += t->offset + t->slope_x * x + t->slope_y * y;
    g[0] += t->slope_x;
    g[1] += t->slope_y;
  } else if (const auto* t = std::get_if<field::BumpTerm>(&term)) {
    const double u = (x - t->center[0]) / t->sigma[0], w = (y - t->center[1]) / t->sigma[1];
    const double zt = t->height * std::exp(-0.5 * (u * u + w * w));
    z += zt;
    g[0] += -zt * (x - t->center[0]) / (t->sigma[0] * t->sigma[0]);
    g[1] += -zt * (y - t->center[1]) / (t->sigma[1] * t->sigma[1]);
  } else if (const auto* t = std::get_if<field::HillTerm>(&term)) {
    const double u = (x - t->crest[0]) * t->direction[0] + (y - t->crest[1]) * t->direction[1];
    if (std::abs(u) >= t->half_width) return;  // the field adds zeros
    z += t->height * 0.5 * (1.0 + std::cos(kPi * u / t->half_width));
    const double dz_du = -t->height * 0.5 * kPi / t->half_width * std::sin(kPi * u / t->half_width);
    g[0] += dz_du * t->direction[0];
    g[1] += dz_du * t->direction[1];
  } else if (const auto* t = std::get_if<field::ArctanTerm>(&term)) {
    const double ax = t->scale_x * (x - t->center[0]), atan_x = std::atan(ax);
    const double dfx = t->amplitude * t->scale_x / (1.0 + ax * ax);
    if (t->scale_y == 0.0) {
      z += t->amplitude * atan_x * 1.0;
      g[0] += dfx;
      return;
    }
    const double ay = t->scale_y * (y - t->center[1]), atan_y = std::atan(ay);
    z += t->amplitude * atan_x * atan_y;
    g[0] += dfx * atan_y;
    g[1] += t->amplitude * atan_x * t->scale_y / (1.0 + ay * ay);
  }
}

// Height z [m] and gradient g of the first n terms at (x, y).
void evaluate(const CompiledSurface& s, int n, double x, double y, double& z, double* g) {
  z = 0.0;
  g[0] = g[1] = 0.0;
  for (int i = 0; i < n; ++i) {
    const auto* pad = std::get_if<field::FlattenTerm>(s.terms[i]);
    if (pad == nullptr) {
      add_term(*s.terms[i], x, y, z, g);
      continue;
    }
    const double dx = x - pad->center[0], dy = y - pad->center[1];
    // Clearly outside the blend (hypot is slow): the field's test below, decided early.
    if (dx * dx + dy * dy > 1.01 * pad->blend_radius * pad->blend_radius) continue;
    const double r = std::hypot(dx, dy);
    if (r >= pad->blend_radius) continue;
    double w, dw_dr;
    pad_weight(*pad, r, w, dw_dr);
    const double dz = s.pad_height[i] - z;
    const double k = r > 0.0 ? dw_dr / r : 0.0;
    g[0] = (1.0 - w) * g[0] + dz * k * dx;
    g[1] = (1.0 - w) * g[1] + dz * k * dy;
    z += w * dz;
  }
}

CompiledSurface compile_surface(const field::Surface& surface) {
  CompiledSurface s;
  const bool simple = surface.terms.size() <= kMaxTerms &&
                      std::none_of(surface.terms.begin(), surface.terms.end(), [](const auto& t) {
                        return std::holds_alternative<field::HeightmapTerm>(t);
                      });
  if (!simple) {
    s.generic = &surface;
    return s;
  }
  s.count = static_cast<int>(surface.terms.size());
  for (int i = 0; i < s.count; ++i) {
    s.terms[i] = &surface.terms[static_cast<std::size_t>(i)];
    if (const auto* pad = std::get_if<field::FlattenTerm>(s.terms[i])) {
      double g[2];
      evaluate(s, i, pad->center[0], pad->center[1], s.pad_height[i], g);
    }
  }
  return s;
}

double surface_height(const CompiledSurface& s, double x, double y) {
  if (s.generic) return s.generic->height(x, y);
  double z, g[2];
  evaluate(s, s.count, x, y, z, g);
  return z;
}

void surface_gradient(const CompiledSurface& s, double x, double y, double* g) {
  if (s.generic) {
    const auto gg = s.generic->gradient(x, y);
    g[0] = gg[0];
    g[1] = gg[1];
    return;
  }
  double z;
  evaluate(s, s.count, x, y, z, g);
}

// ---------------------------------------------------------------------------------------------
// The ball-ground contact as MuJoCo 2.2.2 builds it for the World's predefined pair.

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

// The ball's predefined pair with `geom`, or -1.
int ball_pair(const mjModel* m, int ball, int geom) {
  for (int i = 0; i < m->npair; ++i)
    if ((m->pair_geom1[i] == ball && m->pair_geom2[i] == geom) ||
        (m->pair_geom2[i] == ball && m->pair_geom1[i] == geom))
      return i;
  return -1;
}

int count_ball_pairs(const mjModel* m, int ball) {
  int n = 0;
  for (int i = 0; i < m->npair; ++i) n += m->pair_geom1[i] == ball || m->pair_geom2[i] == ball;
  return n;
}

// What the closed form assumes of the model; false: fast_putt runs simulate_putt.
bool model_fits(const World& world) {
  const mjModel* m = world.model();
  const WorldIds& ids = world.ids();
  const int pair = ball_pair(m, ids.ball_geom, ids.ground_geom);
  const int b = ids.ball_body, dof = ids.ball_dof;
  // Ball touches only ground, 4 borders, the obstacles and the cup (floor and walls).
  const int expected_pairs =
      1 + 4 + static_cast<int>(world.field().obstacles.size()) + 1 + world.options().hole_segments;
  bool fits =
      world.options().ground == GroundContact::kTangentPlane && m->nv == 6 &&
      world.field().obstacles.size() <= field::kMaxObstacles && m->nu == 0 && m->na == 0 &&
      pair >= 0 && count_ball_pairs(m, ids.ball_geom) == expected_pairs && m->pair_dim[pair] == 3 &&
      m->pair_margin[pair] == 0.0 && m->pair_gap[pair] == 0.0 && m->pair_solref[2 * pair] > 0.0 &&
      m->pair_friction[5 * pair] == m->pair_friction[5 * pair + 1] &&
      m->opt.cone == mjCONE_ELLIPTIC && m->opt.integrator == mjINT_EULER &&
      m->opt.solver == mjSOL_NEWTON && m->opt.noslip_iterations == 0 && m->opt.disableflags == 0 &&
      m->opt.enableflags == 0 && m->body_inertia[3 * b] == m->body_inertia[3 * b + 1] &&
      m->body_inertia[3 * b] == m->body_inertia[3 * b + 2];
  for (int k = 0; k < 6 && fits; ++k)
    fits = m->dof_damping[dof + k] == 0.0 && m->dof_armature[dof + k] == 0.0 &&
           m->dof_frictionloss[dof + k] == 0.0;
  return fits;
}

GroundModel ground_model(const World& world) {
  const mjModel* m = world.model();
  const WorldIds& ids = world.ids();
  const int pair = ball_pair(m, ids.ball_geom, ids.ground_geom);
  GroundModel g;
  g.radius = world.field().ball.radius;
  g.mass = m->body_mass[ids.ball_body];
  g.inertia = m->body_inertia[3 * ids.ball_body];
  g.timestep = m->opt.timestep;
  for (int k = 0; k < 3; ++k) g.gravity[k] = m->opt.gravity[k];
  g.friction = m->pair_friction[5 * pair];
  g.impratio = std::max(mjMINVAL, m->opt.impratio);
  g.mu = g.friction / std::sqrt(g.impratio);
  for (int k = 0; k < 5; ++k) g.solimp[k] = m->pair_solimp[5 * pair + k];
  g.imp_below = 1.0 / std::pow(g.solimp[3], g.solimp[4] - 1.0);
  g.imp_above = 1.0 / std::pow(1.0 - g.solimp[3], g.solimp[4] - 1.0);
  // MuJoCo's reference acceleration (mj_makeImpedance): time constant at least two steps.
  const double dmax = std::clamp(g.solimp[1], mjMINIMP, mjMAXIMP);
  const double tc = std::max(m->pair_solref[2 * pair], 2.0 * g.timestep);
  const double ratio = m->pair_solref[2 * pair + 1];
  g.stiffness = 1.0 / (dmax * dmax * tc * tc * ratio * ratio);
  g.damping = 2.0 / (dmax * tc);
  const int ground_body = m->geom_bodyid[ids.ground_geom];
  g.diag = m->body_invweight0[2 * ids.ball_body] + m->body_invweight0[2 * ground_body];
  g.rho = world.field().rolling_resistance;
  g.slip_limit = world.options().rolling_slip_limit;
  g.smoothing = world.options().resistance_smoothing;
  return g;
}

// MuJoCo's constraint impedance at penetration `pos` [m] (solimp's power sigmoid, as
// mj_makeImpedance computes it).
double impedance(const GroundModel& gm, double pos) {
  const auto& solimp = gm.solimp;
  const double dmin = std::clamp(solimp[0], mjMINIMP, mjMAXIMP);
  const double dmax = std::clamp(solimp[1], mjMINIMP, mjMAXIMP);
  if (dmin == dmax || solimp[2] <= mjMINVAL) return 0.5 * (dmin + dmax);
  const double x = std::abs(pos / solimp[2]), mid = solimp[3], power = solimp[4];
  if (x >= 1.0 || x <= 0.0) return x >= 1.0 ? dmax : dmin;
  double y;
  if (power == 1.0) {
    y = x;
  } else if (x <= mid) {
    y = gm.imp_below * std::pow(x, power);
  } else {
    y = 1.0 - gm.imp_above * std::pow(1.0 - x, power);
  }
  return dmin + y * (dmax - dmin);
}

// ---------------------------------------------------------------------------------------------
// One step of the ball on the ground.

using Vec3 = std::array<double, 3>;

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// The ball's state between steps (world frame).
struct Ball {
  Vec3 c{};             ///< centre [m]
  Vec3 v{};             ///< [m/s]
  Vec3 w{};             ///< angular velocity [rad/s]
  Vec3 a{}, alpha{};    ///< last accelerations [m/s^2], [rad/s^2] (MuJoCo's warm start)
  double normal = 0.0;  ///< last ground normal force [N] (World::step's rolling resistance)
};

/// The tangent plane World::update_ground_contact puts under the ball: the same three
/// fixed-point iterations for the foot point.
struct Plane {
  Vec3 point{}, n{};  ///< a point on it [m] and its unit normal (up)
};

Plane ground_plane(const CompiledSurface& s, const Vec3& c, double r) {
  double px = c[0], py = c[1], g[2];
  Plane p;
  for (int it = 0; it < 3; ++it) {
    surface_gradient(s, px, py, g);
    const double inv = 1.0 / std::sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
    p.n = {-g[0] * inv, -g[1] * inv, inv};
    px = c[0] - r * p.n[0];
    py = c[1] - r * p.n[1];
  }
  p.point = {px, py, surface_height(s, px, py)};
  return p;
}

// World::step's rolling-resistance torque [N m] for a ball touching ground of normal n.
Vec3 rolling_torque(const GroundModel& gm, const Ball& b, const Vec3& n) {
  const double along = dot(b.w, n);
  Vec3 roll;
  for (int k = 0; k < 3; ++k) roll[k] = b.w[k] - along * n[k];
  const double spin = std::sqrt(dot(roll, roll));
  // Slip of the contact point v + w x (-r n): resistance fades out while the ball slides.
  Vec3 slip = cross(b.w, {-gm.radius * n[0], -gm.radius * n[1], -gm.radius * n[2]});
  for (int k = 0; k < 3; ++k) slip[k] += b.v[k];
  const double slip_n = dot(slip, n);
  for (int k = 0; k < 3; ++k) slip[k] -= slip_n * n[k];
  const double rolling =
      std::clamp((gm.slip_limit - std::sqrt(dot(slip, slip))) / (0.5 * gm.slip_limit), 0.0, 1.0);
  if (!(spin > 0.0 && rolling > 0.0)) return {0.0, 0.0, 0.0};
  const double magnitude =
      rolling * gm.rho * gm.radius * b.normal * std::min(1.0, spin / gm.smoothing);
  return {-magnitude * roll[0] / spin, -magnitude * roll[1] / spin, -magnitude * roll[2] / spin};
}

/// The contact force on the ball [N]: along the normal and in the tangent plane.
struct ContactForce {
  double normal = 0.0;
  Vec3 tangent{};
};

// MuJoCo's soft contact force for penetration `dist` < 0 [m] (the optimum of its convex
// problem for this one contact, in closed form). The contact point lies `lever` [m] below the
// centre; a0, alpha0: the ball's accelerations without the contact. In contact space
// J M^-1 J' is diagonal (1/m normal, 1/m + lever^2/I tangential), so the optimum is free (no
// force), quadratic (sticking: f = -D jar) or on the cone (sliding: a 2x2 linear system).
ContactForce contact_force(const GroundModel& gm, const Ball& b, const Vec3& n, double dist,
                           double lever, const Vec3& a0, const Vec3& alpha0) {
  const double imp = impedance(gm, dist);
  const double r_normal = std::max(mjMINVAL, (1.0 - imp) * gm.diag / imp);
  const double d_normal = 1.0 / r_normal, d_tangent = gm.impratio / r_normal;
  // Reference accelerations: damping on the velocities, stiffness on the penetration.
  const double aref_n = -gm.damping * dot(b.v, n) - gm.stiffness * imp * dist;
  const Vec3 wxn = cross(b.w, n), axn = cross(alpha0, n);
  Vec3 jt;  // tangential: a0's slip acceleration minus the reference (-B slip)
  for (int k = 0; k < 3; ++k)
    jt[k] = a0[k] - lever * axn[k] + gm.damping * (b.v[k] - lever * wxn[k]);
  const double jt_n = dot(jt, n);
  for (int k = 0; k < 3; ++k) jt[k] -= jt_n * n[k];
  const double jn0 = dot(a0, n) - aref_n, s0 = std::sqrt(dot(jt, jt));
  const double an = 1.0 / gm.mass, at = 1.0 / gm.mass + lever * lever / gm.inertia;
  const double mu = gm.mu, fr = gm.friction;
  ContactForce f;
  if (jn0 >= fr * s0) return f;  // separating: no force
  double ft;                     // along jt [N]
  const double jn_q = jn0 / (1.0 + an * d_normal), s_q = s0 / (1.0 + at * d_tangent);
  if (mu * mu * jn_q + fr * s_q <= 0.0) {
    f.normal = -d_normal * jn_q;
    ft = -d_tangent * s_q;
  } else {
    // On the cone: cost Dm (N - mu T)^2 / 2 with N = mu jn, T = fr |jt|.
    const double dm = d_normal / (mu * mu * (1.0 + mu * mu)), k = dm * mu * mu;
    const double a11 = 1.0 + an * k, a12 = -an * k * fr, a21 = -at * k * fr;
    const double a22 = 1.0 + at * k * fr * fr, det = a11 * a22 - a12 * a21;
    const double jn = (jn0 * a22 - a12 * s0) / det, s = (a11 * s0 - a21 * jn0) / det;
    const double n_minus_t = mu * jn - mu * fr * s;
    f.normal = -dm * n_minus_t * mu;
    ft = dm * n_minus_t * mu * fr;
  }
  if (s0 > 0.0)
    for (int k = 0; k < 3; ++k) f.tangent[k] = ft * jt[k] / s0;
  return f;
}

/// What a closed-form step found.
enum class GroundStep {
  kTouching,  ///< stepped, the ball pressed on the ground
  kInAir,     ///< stepped, no ground contact
  kTooDeep,   ///< not stepped: the centre sank into the ground box, which MuJoCo resolves
};

// The ground is a box 2 cm thick: it acts as a plane only while the centre is above its top face.
// Deeper (a ball landing from a high hop) MuJoCo pushes the ball out of another face.
constexpr double kMaxPenetration = 0.5;  // [ball radii]

// One timestep of the ball touching nothing but the ground: World::step (ground under the ball,
// rolling resistance from the last normal force) and MuJoCo's step (contact, Euler).
GroundStep ground_step(const GroundModel& gm, const CompiledSurface& s, Ball& b) {
  const Plane p = ground_plane(s, b.c, gm.radius);
  const Vec3 rel{b.c[0] - p.point[0], b.c[1] - p.point[1], b.c[2] - p.point[2]};
  const double dist = dot(p.n, rel) - gm.radius;  // < 0: penetration
  if (dist < -kMaxPenetration * gm.radius) return GroundStep::kTooDeep;
  const Vec3 torque =
      dist <= 0.0 && b.normal > 0.0 ? rolling_torque(gm, b, p.n) : Vec3{0.0, 0.0, 0.0};
  Vec3 a = gm.gravity;
  Vec3 alpha{torque[0] / gm.inertia, torque[1] / gm.inertia, torque[2] / gm.inertia};
  ContactForce f;
  if (dist < 0.0) {
    // MuJoCo's contact point: midway through the penetration.
    const double lever = gm.radius + 0.5 * dist;
    f = contact_force(gm, b, p.n, dist, lever, a, alpha);
    const Vec3 arm = cross(p.n, f.tangent);
    for (int k = 0; k < 3; ++k) {
      a[k] += (f.normal * p.n[k] + f.tangent[k]) / gm.mass;
      alpha[k] += -lever * arm[k] / gm.inertia;
    }
  }
  const double h = gm.timestep;
  for (int k = 0; k < 3; ++k) {
    b.v[k] += h * a[k];
    b.w[k] += h * alpha[k];
    b.c[k] += h * b.v[k];
  }
  b.a = a;
  b.alpha = alpha;
  b.normal = f.normal;
  return dist < 0.0 ? GroundStep::kTouching : GroundStep::kInAir;
}

// ---------------------------------------------------------------------------------------------
// Where the ball may touch something besides the ground.

/// An obstacle's footprint: centre and half lengths [m], its yaw's cosine and sine.
struct Box2 {
  double cx, cy, hx, hy, cos_yaw, sin_yaw;
};

/// Lane borders, obstacles and the cup, as reach of the ball's centre.
struct Obstacles {
  double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;  ///< centre beyond these: at a border [m]
  int count = 0;
  std::array<Box2, field::kMaxObstacles> boxes{};
  double reach = 0.0;                                   ///< ... closer than this to an obstacle [m]
  double hole_x = 0.0, hole_y = 0.0, hole_reach = 0.0;  ///< ... or to the hole's centre [m]
};

// Contacts start at zero distance: this much more covers rounding in MuJoCo's geometry [m].
constexpr double kSafety = 1e-5;

Obstacles obstacles_of(const World& world, std::array<double, 2> hole) {
  const field::Field& f = world.field();
  const mjModel* m = world.model();
  Obstacles o;
  const double r = f.ball.radius, reach = r + kSafety;
  o.x0 = f.bounds[0] + reach;
  o.x1 = f.bounds[1] - reach;
  o.y0 = f.bounds[2] + reach;
  o.y1 = f.bounds[3] - reach;
  for (const field::Obstacle& ob : f.obstacles) {  // at most kMaxObstacles (model_fits)
    const field::Footprint fp = ob.footprint();
    o.boxes[static_cast<std::size_t>(o.count++)] = {
        fp.center[0], fp.center[1], fp.half[0], fp.half[1], std::cos(fp.yaw), std::sin(fp.yaw)};
  }
  o.reach = reach;
  // The cup's wall boxes reach out to hypot(R + thickness, half length); a cup tilted with a
  // sloped hole shifts them by up to (depth + its lowering) times the slope.
  const mjtNum* size = m->geom_size + 3 * world.ids().first_wall_geom;
  const double hole_r = 0.5 * f.hole.diameter;
  const auto g = f.surface.gradient(hole[0], hole[1]);
  const double tilt = std::hypot(g[0], g[1]) * (f.hole.depth + hole_r * std::hypot(g[0], g[1]));
  o.hole_x = hole[0];
  o.hole_y = hole[1];
  o.hole_reach = std::hypot(hole_r + 2.0 * size[0], size[1]) + tilt + reach;
  return o;
}

// Horizontal distance [m] the ball's centre may move before it can touch a border, an obstacle or
// the cup (<= 0: it may touch one now).
double clearance(const Obstacles& o, const Vec3& c) {
  double free = std::min({c[0] - o.x0, o.x1 - c[0], c[1] - o.y0, o.y1 - c[1]});
  for (int i = 0; i < o.count; ++i) {
    const Box2& b = o.boxes[static_cast<std::size_t>(i)];
    const double rx = c[0] - b.cx, ry = c[1] - b.cy;
    const double qx = std::abs(b.cos_yaw * rx + b.sin_yaw * ry) - b.hx;
    const double qy = std::abs(-b.sin_yaw * rx + b.cos_yaw * ry) - b.hy;
    const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
    free = std::min(free, outside + std::min(std::max(qx, qy), 0.0) - o.reach);
  }
  return std::min(free, std::hypot(c[0] - o.hole_x, c[1] - o.hole_y) - o.hole_reach);
}

// ---------------------------------------------------------------------------------------------
// Hand-offs between the closed form and the MuJoCo world.

void to_mujoco(const World& world, mjData* d, const Ball& b, double time) {
  BallState s;
  for (int k = 0; k < 3; ++k) {
    s.qpos[k] = b.c[k];
    s.qvel[k] = b.v[k];
    s.qvel[k + 3] = b.w[k];  // identity orientation: body = world
    s.qacc_warmstart[k] = b.a[k];
    s.qacc_warmstart[k + 3] = b.alpha[k];
  }
  s.qpos[3] = 1.0;  // a sphere's orientation does not change its motion
  s.ground_normal = b.normal;
  s.time = time;
  world.set_ball_state(d, s);
}

Ball from_mujoco(const World& world, const mjData* d) {
  const BallState s = world.ball_state(d);
  Ball b;
  mjtNum w[3];
  mju_rotVecQuat(w, s.qvel.data() + 3, s.qpos.data() + 3);
  mjtNum a[3];
  mju_rotVecQuat(a, s.qacc_warmstart.data() + 3, s.qpos.data() + 3);
  for (int k = 0; k < 3; ++k) {
    b.c[k] = s.qpos[k];
    b.v[k] = s.qvel[k];
    b.w[k] = w[k];
    b.a[k] = s.qacc_warmstart[k];
    b.alpha[k] = a[k];
  }
  b.normal = s.ground_normal;
  return b;
}

// simulate_putt's start (checks, launch, the same bits in `d`), and the ball it launched.
Ball started(const World& world, mjData* d, std::array<double, 2> hole,
             const PuttRequest& request) {
  start_putt(world, d, hole, request);
  return from_mujoco(world, d);
}

/// What the ball touched in `d`'s last step.
struct Touching {
  bool ground = false;  ///< the ground or the cup floor
  bool wall = false;    ///< a border, an obstacle or a cup wall
};

Touching touching(const World& world, const mjData* d) {
  Touching t;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.dist >= 0.0) continue;
    (world.is_ball_ground(c) ? t.ground : t.wall) = true;
  }
  return t;
}

// ---------------------------------------------------------------------------------------------
// The hybrid run.

constexpr double kNever = 1e300;       // [s] a time not reached
constexpr double kCalmRollTime = 0.1;  // [s] on the ground this long before a replay ends

class HybridPutt {
 public:
  HybridPutt(const World& world, mjData* d, std::array<double, 2> hole, const PuttRequest& request,
             const OutcomeRules& rules, const FastPuttOptions& options)
      : world_(world),
        d_(d),
        hole_(hole),
        request_(request),
        rules_(rules),
        options_(options),
        gm_(ground_model(world)),
        surface_(compile_surface(world.field().surface)),
        obstacles_(obstacles_of(world, hole)),
        ball_(started(world, d, hole, request)),
        tracker_(world, d, rules) {
    const double h = gm_.timestep;
    record_every_ = request.record_interval > 0.0
                        ? std::max(1, static_cast<int>(std::lround(request.record_interval / h)))
                        : 0;
    max_steps_ = static_cast<int>(std::ceil(request.max_duration / h));
    if (record_every_) {
      trajectory_.reserve(static_cast<std::size_t>(max_steps_ / record_every_ + 2));
      record();
    }
  }

  PuttOutcome run() {
    bool decided = false;
    while (steps_ < max_steps_ && !decided) {
      if (!in_mujoco_ && !exact_ && free_path_ <= 0.0) {
        free_path_ = clearance(obstacles_, ball_.c);
        if (free_path_ <= 0.0) to_mujoco(world_, d_, ball_, t_);
        in_mujoco_ = free_path_ <= 0.0;
      }
      if (in_mujoco_ || exact_ || !step_ground()) step_mujoco();
      ++steps_;
      decided = tracker_.update(t_, ball_.c.data(), ball_.v.data());
      if (record_every_ && (steps_ % record_every_ == 0 || decided)) record();
      if (exact_ && steps_ >= exact_until_ && calm()) {
        exact_ = false;
        airtime_ = 0.0;
        wall_hits_ = 0;
      }
      if (!decided && !exact_ && chaotic()) replay();
    }
    PuttOutcome out = tracker_.outcome();
    out.steps = mujoco_steps_;
    if (!decided) out.end = PuttEnd::kTimeOut;
    out.trajectory = std::move(trajectory_);
    return out;
  }

 private:
  // A closed-form step; false (nothing done) when MuJoCo must take it.
  bool step_ground() {
    const GroundStep result = ground_step(gm_, surface_, ball_);
    if (result == GroundStep::kTooDeep) {
      to_mujoco(world_, d_, ball_, t_);
      return false;
    }
    t_ += gm_.timestep;
    track_contact(result == GroundStep::kTouching);
    at_wall_ = false;
    free_path_ -= gm_.timestep * std::sqrt(ball_.v[0] * ball_.v[0] + ball_.v[1] * ball_.v[1]);
    return true;
  }

  void track_contact(bool touching) {
    if (!touching) airtime_ += gm_.timestep;
    grounded_since_ = touching ? std::min(grounded_since_, t_) : kNever;
  }

  void step_mujoco() {
    world_.step(d_);
    ++mujoco_steps_;
    ball_ = from_mujoco(world_, d_);
    t_ = d_->time;
    const Touching now = touching(world_, d_);
    track_contact(now.ground);
    if (now.wall && !at_wall_ && std::hypot(ball_.v[0], ball_.v[1]) > options_.wall_hit_speed)
      ++wall_hits_;
    at_wall_ = now.wall;
    free_path_ = clearance(obstacles_, ball_.c);
    in_mujoco_ = free_path_ <= 0.0;
  }

  // Starts over in MuJoCo exactly as simulate_putt does (the same bits) and stays there until
  // the ball is past this step and calm: hops off walls make MuJoCo's own putts chaotic (a
  // rounding-level difference grows ~10x per hop), so only its own steps reproduce them.
  void replay() {
    exact_until_ = steps_;
    start_putt(world_, d_, hole_, request_);
    tracker_ = OutcomeTracker(world_, d_, rules_);
    ball_ = from_mujoco(world_, d_);
    t_ = d_->time;
    steps_ = 0;
    grounded_since_ = kNever;
    exact_ = in_mujoco_ = true;
    trajectory_.clear();
    if (record_every_) record();
  }

  // Hopping off walls for long enough that MuJoCo's own putt is chaotic (FastPuttOptions).
  bool chaotic() const {
    if (options_.replay_airtime <= 0.0) return false;
    const double hits = options_.replay_wall_hits > 0
                            ? static_cast<double>(wall_hits_) / options_.replay_wall_hits
                            : 0.0;
    return airtime_ / options_.replay_airtime + hits >= 1.0;
  }

  // Rolling (on the ground for a while) and too slow to hop off a wall again.
  bool calm() const {
    return std::hypot(ball_.v[0], ball_.v[1]) < options_.calm_speed &&
           t_ - grounded_since_ >= kCalmRollTime;
  }

  void record() {
    trajectory_.push_back(
        {t_, ball_.c[0], ball_.c[1], ball_.c[2], ball_.v[0], ball_.v[1], ball_.v[2]});
  }

  const World& world_;
  mjData* d_;
  std::array<double, 2> hole_;
  const PuttRequest& request_;
  OutcomeRules rules_;
  FastPuttOptions options_;
  GroundModel gm_;
  CompiledSurface surface_;
  Obstacles obstacles_;
  Ball ball_;
  OutcomeTracker tracker_;
  std::vector<BallSample> trajectory_;
  int record_every_ = 0, max_steps_ = 0, steps_ = 0, mujoco_steps_ = 0, exact_until_ = 0;
  int wall_hits_ = 0;     ///< fast hits of walls (since the start or the last calm)
  bool at_wall_ = false;  ///< touching a wall in the last MuJoCo step
  double t_ = 0.0;        ///< [s]
  double airtime_ = 0.0;  ///< [s] without ground contact (since the start or the last calm)
  double grounded_since_ = kNever;  ///< [s] on the ground since (kNever: in the air)
  double free_path_ = 0.0;          ///< [m] the ball may move this far before clearance is checked
  bool in_mujoco_ = false;  ///< the MuJoCo world steps the ball (it may touch more than ground)
  bool exact_ = false;      ///< replaying in MuJoCo from the start (see replay)
};

}  // namespace

bool fast_putt_applies(const World& world) { return model_fits(world); }

PuttOutcome fast_putt(const World& world, mjData* d, std::array<double, 2> hole,
                      const PuttRequest& request, const OutcomeRules& rules,
                      const FastPuttOptions& options) {
  if (!model_fits(world)) return simulate_putt(world, d, hole, request, rules);
  return HybridPutt(world, d, hole, request, rules, options).run();
}

}  // namespace mg::sim
