#include "sim/world.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "sim/world_mjcf.hpp"

namespace mg::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

void WorldOptions::validate() const {
  require_in_range("world.timestep", timestep, 1e-4, 0.002);
  if (hole_segments < 8 || hole_segments > 128)
    throw InputError(fmt::format("world.hole_segments: expected 8..128, got {}", hole_segments));
  require_in_range("world.resistance_smoothing", resistance_smoothing, 1e-4, 1.0);
  require_in_range("world.cup_restitution", cup_restitution, 0.0, 0.95);
  require_in_range("world.rolling_slip_limit", rolling_slip_limit, 1e-3, 1.0);
  require_in_range("world.ground_time_constant", ground_time_constant, 2.0 * timestep, 0.1);
}

World::World(field::Field field, const WorldOptions& options)
    : field_(std::move(field)), options_(options) {
  static std::atomic<std::uint64_t> next_instance_id{1};
  instance_id_ = next_instance_id.fetch_add(1);
  options_.validate();
  field_.validate();
  mjcf_ = build_world_mjcf(field_, options_);
  model_ = compile_mjcf(mjcf_);
  if (options_.ground == GroundContact::kTangentPlane) {
    // The same contacts from predefined pairs only (MuJoCo's order: see predefined_pairs).
    mjcf_ = world_mjcf(field_, options_, predefined_pairs(model_.get()));
    model_ = compile_mjcf(mjcf_);
  }

  mjModel* m = model_.get();
  ids_.ball_body = mj_name2id(m, mjOBJ_BODY, "ball");
  ids_.ball_geom = mj_name2id(m, mjOBJ_GEOM, "ball");
  const int ball_joint = mj_name2id(m, mjOBJ_JOINT, "ball");
  ids_.ball_qpos = m->jnt_qposadr[ball_joint];
  ids_.ball_dof = m->jnt_dofadr[ball_joint];
  const bool heightfield = options_.ground == GroundContact::kHeightfield;
  ids_.ground_geom = mj_name2id(m, mjOBJ_GEOM, heightfield ? "lane_contact" : "ground");
  ids_.ground_mocap = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "ground_contact")];
  if (heightfield) {
    const int lane = mj_name2id(m, mjOBJ_BODY, "lane_contact");
    ids_.lane_contact_mocap = m->body_mocapid[lane];
    std::copy_n(m->body_pos + 3 * lane, 3, lane_contact_pos_.begin());
  }
  ids_.surface_geom = mj_name2id(m, mjOBJ_GEOM, "lane_surface");
  ids_.hole_floor_geom = mj_name2id(m, mjOBJ_GEOM, "hole_floor");
  ids_.hole_mocap = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "hole")];
  ids_.first_wall_geom = mj_name2id(m, mjOBJ_GEOM, "hole_wall_0");
  if (options_.cup == CupBodies::kPerSegment)
    ids_.first_wall_mocap = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "hole_wall_0")];

  // Fill the heightfield from the surface function (normalised to [0, 1] of the elevation).
  const int hf = 0;
  const int nrow = m->hfield_nrow[hf], ncol = m->hfield_ncol[hf];
  const double elevation = m->hfield_size[4 * hf + 2];
  const double z0 = m->geom_pos[3 * ids_.surface_geom + 2];
  const auto& b = field_.bounds;
  float* data = m->hfield_data + m->hfield_adr[hf];
  for (int r = 0; r < nrow; ++r)
    for (int c = 0; c < ncol; ++c) {
      const double z = field_.height(b[0] + (b[1] - b[0]) * c / (ncol - 1),
                                     b[2] + (b[3] - b[2]) * r / (nrow - 1));
      data[r * ncol + c] = static_cast<float>(std::clamp((z - z0) / elevation, 0.0, 1.0));
    }

  walls_ = make_walls(field_);
  walls_.inertia_ratio = m->body_inertia[3 * ids_.ball_body] /
                         (m->body_mass[ids_.ball_body] * field_.ball.radius * field_.ball.radius);
  fine_model_.reset(mj_copyModel(nullptr, model_.get()));
  fine_model_->opt.timestep = model_->opt.timestep / kImpactSubsteps;
}

DataPtr World::make_data() const {
  DataPtr d(mj_makeData(model_.get()));
  if (!d) throw Error("MuJoCo: cannot allocate simulation data");
  reset(d.get());
  return d;
}

void World::reset(mjData* d) const {
  mj_resetData(model_.get(), d);
  d->userdata[kUserGroundNormal] = 0.0;
  set_hole(d, field_.hole.position);
  place_ball(d, field_.tee);
}

void World::set_hole(mjData* d, std::array<double, 2> p) const {
  field::check_hole_position(field_, p);
  const double r = 0.5 * field_.hole.diameter;
  const double zc = field_.height(p[0], p[1]);
  const auto g = field_.surface.gradient(p[0], p[1]);
  const double rim_drop = std::hypot(g[0], g[1]) * r;
  if (rim_drop + 0.002 > field_.hole.depth)
    throw InputError(
        fmt::format("hole position: ground at ({}, {}) is too steep for a hole {} m "
                    "deep (the rim drops {:.3f} m across it)",
                    p[0], p[1], field_.hole.depth, rim_drop));
  d->userdata[kUserHoleX] = p[0];
  d->userdata[kUserHoleY] = p[1];
  d->userdata[kUserHoleRadius] = r;
  if (options_.cup == CupBodies::kPerSegment) {
    set_segmented_cup(d, p);
    return;
  }
  // The cup's plane: the tangent plane at the hole, lowered along its normal just enough that no
  // wall top sticks out of the ground at its chord's centre and ends (the rule of kPerSegment's
  // vertical walls; zero on a plane).
  const double inv = 1.0 / std::sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
  const double n[3] = {-g[0] * inv, -g[1] * inv, inv};
  const int segments = options_.hole_segments;
  const double half = r * std::tan(kPi / segments);
  double drop = 0.0;
  for (int i = 0; i < segments; ++i) {
    const double phi = 2.0 * kPi * i / segments;
    const double ux = std::cos(phi), uy = std::sin(phi);
    for (double s : {-half, 0.0, half}) {
      const double x = p[0] + r * ux - s * uy, y = p[1] + r * uy + s * ux;
      const double plane = zc + g[0] * (x - p[0]) + g[1] * (y - p[1]);
      drop = std::max(drop, (plane - field_.height(x, y)) * inv);
    }
  }
  mjtNum* pos = d->mocap_pos + 3 * ids_.hole_mocap;
  pos[0] = p[0] - drop * n[0];
  pos[1] = p[1] - drop * n[1];
  pos[2] = zc - drop * n[2];
  // Rotation taking +z to n, about the horizontal axis z x n (as update_ground_contact).
  mjtNum* quat = d->mocap_quat + 4 * ids_.hole_mocap;
  const double s = std::hypot(n[0], n[1]);
  if (s < 1e-12) {
    quat[0] = 1.0;
    quat[1] = quat[2] = quat[3] = 0.0;
  } else {
    const double half_angle = 0.5 * std::atan2(s, n[2]);
    quat[0] = std::cos(half_angle);
    quat[1] = -n[1] / s * std::sin(half_angle);
    quat[2] = n[0] / s * std::sin(half_angle);
    quat[3] = 0.0;
  }
}

void World::set_segmented_cup(mjData* d, std::array<double, 2> p) const {
  const double r = 0.5 * field_.hole.diameter;
  mjtNum* floor = d->mocap_pos + 3 * ids_.hole_mocap;
  floor[0] = p[0];
  floor[1] = p[1];
  floor[2] = field_.height(p[0], p[1]) - field_.hole.depth;
  const int n = options_.hole_segments;
  const double seg_t = 0.01;
  for (int i = 0; i < n; ++i) {
    const double phi = 2.0 * kPi * i / n;
    const double ux = std::cos(phi), uy = std::sin(phi);
    // Top of the segment at the lowest ground along its chord, so it never sticks out.
    const double half = r * std::tan(kPi / n);
    double top = field_.height(p[0] + r * ux, p[1] + r * uy);
    for (double s : {-half, half})
      top = std::min(top, field_.height(p[0] + r * ux - s * uy, p[1] + r * uy + s * ux));
    mjtNum* pos = d->mocap_pos + 3 * (ids_.first_wall_mocap + i);
    pos[0] = p[0] + (r + 0.5 * seg_t) * ux;
    pos[1] = p[1] + (r + 0.5 * seg_t) * uy;
    pos[2] = top;
    mjtNum* quat = d->mocap_quat + 4 * (ids_.first_wall_mocap + i);
    quat[0] = std::cos(0.5 * phi);
    quat[1] = 0.0;
    quat[2] = 0.0;
    quat[3] = std::sin(0.5 * phi);
  }
}

std::array<double, 2> World::hole_position(const mjData* d) const {
  return {d->userdata[kUserHoleX], d->userdata[kUserHoleY]};
}

BallState World::ball_state(const mjData* d) const {
  BallState s;
  std::copy_n(d->qpos + ids_.ball_qpos, 7, s.qpos.begin());
  std::copy_n(d->qvel + ids_.ball_dof, 6, s.qvel.begin());
  std::copy_n(d->qacc_warmstart + ids_.ball_dof, 6, s.qacc_warmstart.begin());
  s.ground_normal = d->userdata[kUserGroundNormal];
  s.time = d->time;
  return s;
}

void World::set_ball_state(mjData* d, const BallState& s) const {
  std::copy_n(s.qpos.begin(), 7, d->qpos + ids_.ball_qpos);
  std::copy_n(s.qvel.begin(), 6, d->qvel + ids_.ball_dof);
  std::copy_n(s.qacc_warmstart.begin(), 6, d->qacc_warmstart + ids_.ball_dof);
  d->userdata[kUserGroundNormal] = s.ground_normal;
  d->time = s.time;
  update_ground_contact(d);
}

void World::place_ball(mjData* d, std::array<double, 2> xy) const {
  mjtNum* q = d->qpos + ids_.ball_qpos;
  q[0] = xy[0];
  q[1] = xy[1];
  q[2] = field_.height(xy[0], xy[1]) + field_.ball.radius;
  q[3] = 1.0;
  q[4] = q[5] = q[6] = 0.0;
  std::fill(d->qvel + ids_.ball_dof, d->qvel + ids_.ball_dof + 6, 0.0);
  update_ground_contact(d);
  mj_forward(model_.get(), d);
}

double World::ground_normal_force(const mjData* d) const {
  double normal = 0.0;
  mjtNum force[6];
  for (int i = 0; i < d->ncon; ++i) {
    if (!is_ball_ground(d->contact[i])) continue;
    mj_contactForce(model_.get(), d, i, force);
    normal += force[0];
  }
  return normal;
}

void World::step(mjData* d) const { step_with(model_.get(), d); }

void World::step_fine(mjData* d) const {
  for (int k = 0; k < kImpactSubsteps; ++k) step_with(fine_model_.get(), d);
}

void World::step_with(const mjModel* m, mjData* d) const {
  update_ground_contact(d);
  mjtNum* centre = d->qpos + ids_.ball_qpos;
  const std::array<double, 3> previous{centre[0], centre[1], centre[2]};
  // Split step: collisions for the current state first, so the rolling-resistance torque acts
  // only while the ball touches the ground now (a torque from the last contact force applied
  // during a hop would spin the ball down in the air).
  mj_step1(m, d);
  mjtNum* torque = d->xfrc_applied + 6 * ids_.ball_body + 3;
  torque[0] = torque[1] = torque[2] = 0.0;
  const double normal_force = d->userdata[kUserGroundNormal];
  mjtNum normal[3] = {0, 0, 0};
  bool touching = false;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (!is_ball_ground(c)) continue;
    touching = true;
    // The contact normal points from geom1 to geom2; we want it out of the ground.
    const double sign = c.geom1 == ids_.ball_geom ? -1.0 : 1.0;
    for (int k = 0; k < 3; ++k) normal[k] += sign * c.frame[k];
  }
  if (touching && normal_force > 0.0) {
    mju_normalize3(normal);
    // Penner: torque rho r N against the rolling part of the spin (spin about the contact
    // normal excluded). A free joint's angular velocity is in the body frame.
    mjtNum spin_world[3];
    mju_rotVecQuat(spin_world, d->qvel + ids_.ball_dof + 3, d->qpos + ids_.ball_qpos + 3);
    mjtNum roll[3];
    const mjtNum along = mju_dot3(spin_world, normal);
    for (int k = 0; k < 3; ++k) roll[k] = spin_world[k] - along * normal[k];
    const double spin = mju_norm3(roll);
    // Slip of the contact point, v + w x (-r n): rolling resistance is a rolling effect; while
    // the ball still slides, kinetic friction governs it (Penner's slide-then-roll model).
    mjtNum arm[3], slip[3];
    for (int k = 0; k < 3; ++k) arm[k] = -field_.ball.radius * normal[k];
    mju_cross(slip, spin_world, arm);
    const mjtNum* v = d->qvel + ids_.ball_dof;
    for (int k = 0; k < 3; ++k) slip[k] += v[k];
    const mjtNum slip_normal = mju_dot3(slip, normal);
    for (int k = 0; k < 3; ++k) slip[k] -= slip_normal * normal[k];
    const double rolling = std::clamp(
        (options_.rolling_slip_limit - mju_norm3(slip)) / (0.5 * options_.rolling_slip_limit), 0.0,
        1.0);
    if (spin > 0.0 && rolling > 0.0) {
      const double magnitude = rolling * field_.rolling_resistance * field_.ball.radius *
                               normal_force * std::min(1.0, spin / options_.resistance_smoothing);
      for (int k = 0; k < 3; ++k) torque[k] = -magnitude * roll[k] / spin;
    }
  }
  mj_step2(m, d);
  d->userdata[kUserGroundNormal] = ground_normal_force(d);
  resolve_wall_contacts(d, previous);
}

void World::resolve_wall_contacts(mjData* d, const std::array<double, 3>& previous) const {
  mjtNum* q = d->qpos + ids_.ball_qpos;
  mjtNum* qv = d->qvel + ids_.ball_dof;
  std::array<double, 3> c{q[0], q[1], q[2]}, v{qv[0], qv[1], qv[2]}, w;
  d->userdata[kUserWallImpact] = 0.0;
  if (wall_clearance(walls_, c) > std::sqrt((c[0] - previous[0]) * (c[0] - previous[0]) +
                                            (c[1] - previous[1]) * (c[1] - previous[1]) +
                                            (c[2] - previous[2]) * (c[2] - previous[2])))
    return;
  mju_rotVecQuat(w.data(), qv + 3, q + 3);  // a free joint's angular velocity is in its body frame
  const WallImpact impact = resolve_walls(walls_, field_, previous, c, v, w);
  if (impact.prism < 0 && c[0] == q[0] && c[1] == q[1] && c[2] == q[2]) return;
  mjtNum inverse[4];
  mju_negQuat(inverse, q + 3);
  mju_rotVecQuat(qv + 3, w.data(), inverse);
  for (int k = 0; k < 3; ++k) {
    q[k] = c[k];
    qv[k] = v[k];
  }
  d->userdata[kUserWallImpact] = impact.normal_speed;
}

double World::wall_impact(const mjData* d) const { return d->userdata[kUserWallImpact]; }

void World::update_ground_contact(mjData* d) const {
  // Foot point p of the ball centre c on the surface: c = p + r n(p), solved by fixed-point
  // iteration on p's horizontal coordinates (converges for curvature radii above r).
  const mjtNum* c = d->qpos + ids_.ball_qpos;
  const double r = field_.ball.radius;
  double px = c[0], py = c[1];
  mjtNum n[3] = {0, 0, 1};
  for (int it = 0; it < 3; ++it) {
    const auto g = field_.surface.gradient(px, py);
    const double inv = 1.0 / std::sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
    n[0] = -g[0] * inv;
    n[1] = -g[1] * inv;
    n[2] = inv;
    px = c[0] - r * n[0];
    py = c[1] - r * n[1];
  }
  mjtNum* pos = d->mocap_pos + 3 * ids_.ground_mocap;
  pos[0] = px;
  pos[1] = py;
  pos[2] = field_.height(px, py);
  // Over the hole opening there is no ground (a heightfield cannot have a hole): while the ball's
  // centre is within the hole's radius, the ground's collision geom is out of reach.
  const double hx = c[0] - d->userdata[kUserHoleX], hy = c[1] - d->userdata[kUserHoleY];
  const double hr = d->userdata[kUserHoleRadius];
  const bool over_hole = hx * hx + hy * hy < hr * hr;
  if (options_.ground == GroundContact::kHeightfield) {
    mjtNum* lane = d->mocap_pos + 3 * ids_.lane_contact_mocap;
    std::copy(lane_contact_pos_.begin(), lane_contact_pos_.end(), lane);
    if (over_hole) lane[2] -= kGroundDrop;
  } else if (over_hole) {
    pos[2] -= kGroundDrop;
  }
  // Rotation taking +z to n, about the horizontal axis z x n.
  mjtNum* quat = d->mocap_quat + 4 * ids_.ground_mocap;
  const double s = std::hypot(n[0], n[1]);
  if (s < 1e-12) {
    quat[0] = 1.0;
    quat[1] = quat[2] = quat[3] = 0.0;
  } else {
    const double half = 0.5 * std::atan2(s, n[2]);
    quat[0] = std::cos(half);
    quat[1] = -n[1] / s * std::sin(half);
    quat[2] = n[0] / s * std::sin(half);
    quat[3] = 0.0;
  }
}

bool World::is_ball_ground(const mjContact& c) const {
  const int other = c.geom1 == ids_.ball_geom ? c.geom2 : c.geom2 == ids_.ball_geom ? c.geom1 : -1;
  return other >= 0 && (other == ids_.ground_geom || other == ids_.hole_floor_geom);
}

}  // namespace mg::sim
