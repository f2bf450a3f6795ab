#include "sim/ground_step.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

namespace mg::sim::ground {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// The lane surface, compiled: height and gradient of the analytic terms in one pass, each
// transcendental evaluated once and a pad's levelled height precomputed (field::Surface
// recomputes both per call: 4-8x slower on the hill fields). Same formulas in the same order as
// src/field/surface.cpp, so the same numbers up to an ulp.

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
    field::pad_weight(*pad, r, w, dw_dr);
    const double dz = s.pad_height[i] - z;
    const double k = r > 0.0 ? dw_dr / r : 0.0;
    g[0] = (1.0 - w) * g[0] + dz * k * dx;
    g[1] = (1.0 - w) * g[1] + dz * k * dy;
    z += w * dz;
  }
}

}  // namespace

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

namespace {

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

}  // namespace

// What the closed form assumes of the model; false: fast_putt runs simulate_putt.
bool model_fits(const World& world) {
  const mjModel* m = world.model();
  const WorldIds& ids = world.ids();
  const int pair = ball_pair(m, ids.ball_geom, ids.ground_geom);
  const int b = ids.ball_body, dof = ids.ball_dof;
  // Ball touches only ground and the cup (floor and walls) in MuJoCo; borders and obstacles are
  // sim/walls' (World::step).
  const int expected_pairs = 1 + 1 + world.options().hole_segments;
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

namespace {

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

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

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

}  // namespace

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

}  // namespace mg::sim::ground
