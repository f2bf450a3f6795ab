#include "sim/world.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"

namespace mg::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGravity = 9.81;

// mjData::userdata layout: the contact filter reads the hole from here, so the filter is a pure
// function of (model, data) and safe with one mjData per thread.
constexpr int kUserMagic = 0, kUserBallGeom = 1, kUserGroundGeom = 2, kUserHoleX = 3,
              kUserHoleY = 4, kUserHoleRadius = 5, kUserGroundNormal = 6, kUserSize = 7;
constexpr double kMagic = 7.2426e6;  // marks an mjData that belongs to a minigolf World

// Collision groups: static geoms only have a contype, so they never collide with each other
// (mocap cup segments would otherwise collide with each other and the ground); the ball has
// every static group in its conaffinity, and the arm's club head (contype 4, see src/robot).
constexpr int kLaneGroup = 1, kCupGroup = 2, kClubGroup = 4, kNoAffinity = 0;

// Removes ball-ground contacts while the ball's centre is over the hole opening: the cup below
// then catches the ball. Otherwise MuJoCo's default contype/conaffinity rule, which a user filter
// replaces, is applied unchanged.
int hole_contact_filter(const mjModel* m, mjData* d, int g1, int g2) {
  const bool bitmask_ok = (m->geom_contype[g1] & m->geom_conaffinity[g2]) ||
                          (m->geom_contype[g2] & m->geom_conaffinity[g1]);
  if (!bitmask_ok) return 1;
  if (m->nuserdata < kUserSize || d->userdata[kUserMagic] != kMagic) return 0;
  const int ball = static_cast<int>(d->userdata[kUserBallGeom]);
  const int ground = static_cast<int>(d->userdata[kUserGroundGeom]);
  if (!((g1 == ball && g2 == ground) || (g1 == ground && g2 == ball))) return 0;
  const mjtNum* p = d->geom_xpos + 3 * ball;
  const double dx = p[0] - d->userdata[kUserHoleX], dy = p[1] - d->userdata[kUserHoleY];
  const double radius = d->userdata[kUserHoleRadius];
  return dx * dx + dy * dy < radius * radius ? 1 : 0;
}

}  // namespace

double damping_ratio_for_restitution(double e) {
  if (e <= 0.0) return 1.0;
  const double l = std::log(e);
  return -l / std::sqrt(kPi * kPi + l * l);
}

void WorldOptions::validate() const {
  require_in_range("world.timestep", timestep, 1e-4, 0.002);
  if (hole_segments < 8 || hole_segments > 128)
    throw InputError(fmt::format("world.hole_segments: expected 8..128, got {}", hole_segments));
  require_in_range("world.resistance_smoothing", resistance_smoothing, 1e-4, 1.0);
  require_in_range("world.cup_restitution", cup_restitution, 0.0, 0.95);
  require_in_range("world.rolling_slip_limit", rolling_slip_limit, 1e-3, 1.0);
  require_in_range("world.ground_time_constant", ground_time_constant, 2.0 * timestep, 0.1);
}

namespace {

// The world's MJCF; with `pairs` (MJCF <pair> elements) MuJoCo tests only those geom pairs.
std::string world_mjcf(const field::Field& f, const WorldOptions& o, const std::string& pairs) {
  const auto& b = f.bounds;
  const int ncol = static_cast<int>(std::lround((b[1] - b[0]) / f.cell_size)) + 1;
  const int nrow = static_cast<int>(std::lround((b[3] - b[2]) / f.cell_size)) + 1;
  double z_min = 1e9, z_max = -1e9;
  for (int r = 0; r < nrow; ++r)
    for (int c = 0; c < ncol; ++c) {
      const double z =
          f.height(b[0] + (b[1] - b[0]) * c / (ncol - 1), b[2] + (b[3] - b[2]) * r / (nrow - 1));
      z_min = std::min(z_min, z);
      z_max = std::max(z_max, z);
    }
  const double elevation = std::max(z_max - z_min, 1e-4);
  const double cx = 0.5 * (b[0] + b[1]), cy = 0.5 * (b[2] + b[3]);
  const double rx = 0.5 * (b[1] - b[0]), ry = 0.5 * (b[3] - b[2]);
  const double wall_t = f.borders.thickness;
  const double wall_bottom = z_min - 0.05, wall_top = z_max + f.borders.height;
  const double wall_hz = 0.5 * (wall_top - wall_bottom), wall_cz = 0.5 * (wall_top + wall_bottom);
  const double wall_zeta = damping_ratio_for_restitution(f.borders.restitution);
  const double hole_r = 0.5 * f.hole.diameter;
  const double seg_half = hole_r * std::tan(kPi / o.hole_segments) + 0.002;
  const double seg_t = 0.01;
  const bool heightfield = o.ground == GroundContact::kHeightfield;

  std::string x;
  x += fmt::format(R"(<mujoco model="minigolf-{}">
  <compiler angle="radian"/>
  <option timestep="{}" gravity="0 0 {}" cone="{}" impratio="{}" collision="{}"/>
  <size nuserdata="{}"/>
  <visual><global offwidth="1280" offheight="720"/></visual>
  <asset>
    <hfield name="lane" nrow="{}" ncol="{}" size="{} {} {} 0.05"/>
  </asset>
  <worldbody>
    <light pos="{} {} 3" dir="0 0 -1" directional="true"/>
    <geom name="lane_surface" type="hfield" hfield="lane" pos="{} {} {}" rgba="0.2 0.6 0.25 1"
          contype="{}" conaffinity="{}" condim="3" priority="1" friction="{} 0 0" solref="{} 1"/>
    <body name="ground_contact" mocap="true" pos="{} {} {}">
      <geom name="ground" type="box" size="0.15 0.15 0.01" pos="0 0 -0.01" rgba="0 0 0 0"
            contype="{}" conaffinity="{}" condim="3" priority="1" friction="{} 0 0"
            solref="{} 1"/>
    </body>
)",
                   f.name, o.timestep, -kGravity, "elliptic", 10,
                   pairs.empty() ? "all" : "predefined", kUserSize, nrow, ncol, rx, ry, elevation,
                   cx, cy, cx, cy, z_min, heightfield ? kLaneGroup : 0, kNoAffinity,
                   f.sliding_friction, o.ground_time_constant, f.tee[0], f.tee[1],
                   f.height(f.tee[0], f.tee[1]), heightfield ? 0 : kLaneGroup, kNoAffinity,
                   f.sliding_friction, o.ground_time_constant);
  const auto wall = [&](const char* name, double px, double py, double hx, double hy) {
    x += fmt::format(
        R"(    <geom name="{}" type="box" pos="{} {} {}" size="{} {} {}" rgba="0.45 0.3 0.2 1"
          contype="{}" conaffinity="{}" condim="3" priority="1" friction="0.2 0 0" solref="0.004 {}"/>
)",
        name, px, py, wall_cz, hx, hy, wall_hz, kLaneGroup, kNoAffinity, wall_zeta);
  };
  wall("border_x_min", b[0] - 0.5 * wall_t, cy, 0.5 * wall_t, ry + wall_t);
  wall("border_x_max", b[1] + 0.5 * wall_t, cy, 0.5 * wall_t, ry + wall_t);
  wall("border_y_min", cx, b[2] - 0.5 * wall_t, rx, 0.5 * wall_t);
  wall("border_y_max", cx, b[3] + 0.5 * wall_t, rx, 0.5 * wall_t);
  // Obstacles: boxes over their footprints, from the borders' bottom to `height` above the
  // highest ground under them, bouncing the ball like the borders with their own restitution.
  for (std::size_t i = 0; i < f.obstacles.size(); ++i) {
    const field::Obstacle& ob = f.obstacles[i];
    const field::Footprint fp = ob.footprint();
    const double c = std::cos(fp.yaw), s = std::sin(fp.yaw);
    double ground = -1e9;
    const int n = 8;
    for (int u = 0; u <= n; ++u)
      for (int v = 0; v <= n; ++v) {
        const double lu = fp.half[0] * (2.0 * u / n - 1.0), lv = fp.half[1] * (2.0 * v / n - 1.0);
        ground = std::max(ground,
                          f.height(fp.center[0] + c * lu - s * lv, fp.center[1] + s * lu + c * lv));
      }
    const double top = ground + ob.height;
    x += fmt::format(
        R"(    <geom name="obstacle_{}" type="box" pos="{} {} {}" size="{} {} {}" quat="{} 0 0 {}"
          rgba="0.55 0.35 0.22 1" contype="{}" conaffinity="{}" condim="3" priority="1"
          friction="0.2 0 0" solref="0.004 {}"/>
)",
        i, fp.center[0], fp.center[1], 0.5 * (top + wall_bottom), fp.half[0], fp.half[1],
        0.5 * (top - wall_bottom), std::cos(0.5 * fp.yaw), std::sin(0.5 * fp.yaw), kLaneGroup,
        kNoAffinity, damping_ratio_for_restitution(ob.restitution));
  }
  x += fmt::format(R"(    <body name="ball" pos="{} {} {}">
      <freejoint name="ball"/>
      <geom name="ball" type="sphere" size="{}" mass="{}" rgba="1 1 1 1"
            contype="{}" conaffinity="{}" condim="3" priority="0"/>
    </body>
)",
                   f.tee[0], f.tee[1], f.height(f.tee[0], f.tee[1]) + f.ball.radius, f.ball.radius,
                   f.ball.mass, kLaneGroup | kCupGroup, kLaneGroup | kCupGroup | kClubGroup);
  const bool one_body = o.cup == CupBodies::kOne;
  // The floor's body is the cup's (kOne) or its own (kPerSegment); its top is at the body's z
  // minus the depth (kOne) or at the body's z (kPerSegment).
  x += fmt::format(R"(    <body name="hole" mocap="true" pos="{} {} {}">
      <geom name="hole_floor" type="cylinder" size="{} 0.005" pos="0 0 {}" rgba="0.1 0.1 0.1 1"
            contype="{}" conaffinity="{}" condim="3" priority="1" friction="0.5 0 0" solref="0.002 1"/>
)",
                   f.hole.position[0], f.hole.position[1], z_min - 1.0, hole_r + seg_t,
                   (one_body ? -f.hole.depth : 0.0) - 0.005, kCupGroup, kNoAffinity);
  if (!one_body) x += "    </body>\n";
  for (int i = 0; i < o.hole_segments; ++i) {
    const double phi = 2.0 * kPi * i / o.hole_segments;
    const double rc = one_body ? hole_r + 0.5 * seg_t : 0.0;
    if (!one_body)
      x += fmt::format(R"(    <body name="hole_wall_{}" mocap="true" pos="0 0 {}">
)",
                       i, z_min - 1.0);
    x += fmt::format(
        R"(      <geom name="hole_wall_{}" type="box" size="{} {} {}" pos="{} {} {}" quat="{} 0 0 {}"
            rgba="0.1 0.1 0.1 1" contype="{}" conaffinity="{}" condim="3" priority="1"
            friction="0.3 0 0" solref="0.004 {}"/>
)",
        i, 0.5 * seg_t, seg_half, 0.5 * f.hole.depth, rc * std::cos(phi), rc * std::sin(phi),
        -0.5 * f.hole.depth, one_body ? std::cos(0.5 * phi) : 1.0,
        one_body ? std::sin(0.5 * phi) : 0.0, kCupGroup, kNoAffinity,
        damping_ratio_for_restitution(o.cup_restitution));
    if (!one_body) x += "    </body>\n";
  }
  if (one_body) x += "    </body>\n";
  x += o.extra_worldbody_mjcf;
  x += "  </worldbody>\n";
  // Static geoms (world, ground box, cup) never touch each other (contype only), but MuJoCo would
  // still test every pair of them each step: 130 pairs, half of all collision work.
  // Static geoms (world, ground box, cup) never touch each other (contype only), but MuJoCo
  // would still test every pair of the world's and the mocap bodies' geoms each step (130
  // pairs, half of all collision work).
  std::vector<std::string> mocap{"ground_contact", "hole"};
  if (!one_body)
    for (int i = 0; i < o.hole_segments; ++i) mocap.push_back(fmt::format("hole_wall_{}", i));
  x += "  <contact>\n";
  const auto exclude = [&x](const std::string& a, const std::string& b) {
    x += fmt::format("    <exclude body1=\"{}\" body2=\"{}\"/>\n", a, b);
  };
  for (const auto& body : mocap) exclude("world", body);
  for (std::size_t i = 1; i < mocap.size(); ++i) exclude("ground_contact", mocap[i]);
  for (const auto& body : o.extra_bodies_off_static) {
    exclude("world", body);
    for (const auto& m : mocap) exclude(m, body);
  }
  for (const auto& body : o.extra_bodies_off_ball) exclude("ball", body);
  x += pairs;
  x += "  </contact>\n";
  if (!o.extra_actuator_mjcf.empty())
    x += "  <actuator>\n" + o.extra_actuator_mjcf + "  </actuator>\n";
  x += "</mujoco>\n";
  return x;
}

ModelPtr compile_mjcf(const std::string& text) {
  // Compile from memory through MuJoCo's virtual file system.
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* kName = "world.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), kName, static_cast<int>(text.size())) != 0)
    throw Error("MuJoCo: cannot create the in-memory model file");
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), kName)], text.data(), text.size());
  char error[1024] = "";
  ModelPtr model;
  {
    // MuJoCo's XML loader keeps the last model in a global (mj_saveLastXML): one at a time.
    static std::mutex load_mutex;
    const std::lock_guard<std::mutex> lock(load_mutex);
    model.reset(mj_loadXML(kName, vfs.get(), error, sizeof error));
  }
  mj_deleteVFS(vfs.get());
  if (!model) throw Error(fmt::format("MuJoCo rejected the generated model: {}", error));
  return model;
}

// Every geom pair MuJoCo's broadphase could hand to the narrow phase of `m` (contype/conaffinity
// compatible, different bodies, body pair not excluded), as <pair> elements with the contact
// parameters MuJoCo 2.2.2 would mix for it (mj_collideGeoms: priority wins, else max/mix), in
// the order the dynamic path visits them (body-pair signature, then geom ids). Testing only
// these skips the broadphase, a quarter of a step.
std::string predefined_pairs(const mjModel* m) {
  std::string x;
  const auto excluded = [m](int b1, int b2) {
    const int signature = ((std::min(b1, b2) + 1) << 16) + std::max(b1, b2) + 1;
    for (int i = 0; i < m->nexclude; ++i)
      if (m->exclude_signature[i] == signature) return true;
    return false;
  };
  const auto num = [](const mjtNum* v, int n) {
    std::string out;
    for (int i = 0; i < n; ++i) out += fmt::format("{}{:.17g}", i ? " " : "", v[i]);
    return out;
  };
  struct Pair {
    int b1, b2, g1, g2;
    std::size_t order;  // discovery order: ties keep it (as stable_sort would, without its buffer)
  };
  std::vector<Pair> pairs;
  for (int g1 = 0; g1 < m->ngeom; ++g1)
    for (int g2 = g1 + 1; g2 < m->ngeom; ++g2) {
      const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
      if (b1 == b2) continue;
      if (!((m->geom_contype[g1] & m->geom_conaffinity[g2]) ||
            (m->geom_contype[g2] & m->geom_conaffinity[g1])))
        continue;
      if (excluded(b1, b2)) continue;
      pairs.push_back(b1 < b2 ? Pair{b1, b2, g1, g2, pairs.size()}
                              : Pair{b2, b1, g2, g1, pairs.size()});
    }
  // std::sort with a total order: std::stable_sort's temporary buffer (operator new, freed by
  // libstdc++ 12 through free) is an alloc-dealloc mismatch under AddressSanitizer.
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return std::tie(a.b1, a.b2, a.order) < std::tie(b.b1, b.b2, b.order);
  });
  for (const Pair& p : pairs) {
    const int g1 = p.g1, g2 = p.g2;
    const char* n1 = mj_id2name(m, mjOBJ_GEOM, g1);
    const char* n2 = mj_id2name(m, mjOBJ_GEOM, g2);
    if (n1 == nullptr || n2 == nullptr)
      throw Error(fmt::format("world: colliding geoms {} and {} need names", g1, g2));
    int condim;
    mjtNum friction[5], solref[mjNREF], solimp[mjNIMP];
    if (m->geom_priority[g1] != m->geom_priority[g2]) {
      const int gp = m->geom_priority[g1] > m->geom_priority[g2] ? g1 : g2;
      condim = m->geom_condim[gp];
      for (int i = 0; i < 3; ++i) friction[2 * i] = m->geom_friction[3 * gp + i];
      std::copy_n(m->geom_solref + mjNREF * gp, mjNREF, solref);
      std::copy_n(m->geom_solimp + mjNIMP * gp, mjNIMP, solimp);
    } else {
      condim = std::max(m->geom_condim[g1], m->geom_condim[g2]);
      for (int i = 0; i < 3; ++i)
        friction[2 * i] = std::max(m->geom_friction[3 * g1 + i], m->geom_friction[3 * g2 + i]);
      const mjtNum s1 = m->geom_solmix[g1], s2 = m->geom_solmix[g2];
      const mjtNum mix = s1 >= mjMINVAL && s2 >= mjMINVAL ? s1 / (s1 + s2)
                         : s1 < mjMINVAL && s2 < mjMINVAL ? 0.5
                         : s1 < mjMINVAL                  ? 0.0
                                                          : 1.0;
      for (int i = 0; i < mjNREF; ++i)
        solref[i] =
            m->geom_solref[mjNREF * g1] > 0 && m->geom_solref[mjNREF * g2] > 0
                ? mix * m->geom_solref[mjNREF * g1 + i] +
                      (1 - mix) * m->geom_solref[mjNREF * g2 + i]
                : std::min(m->geom_solref[mjNREF * g1 + i], m->geom_solref[mjNREF * g2 + i]);
      for (int i = 0; i < mjNIMP; ++i)
        solimp[i] =
            mix * m->geom_solimp[mjNIMP * g1 + i] + (1 - mix) * m->geom_solimp[mjNIMP * g2 + i];
    }
    friction[1] = friction[0];
    friction[3] = friction[4];
    const mjtNum margin = std::max(m->geom_margin[g1], m->geom_margin[g2]);
    const mjtNum gap = std::max(m->geom_gap[g1], m->geom_gap[g2]);
    x += fmt::format(
        "    <pair geom1=\"{}\" geom2=\"{}\" condim=\"{}\" friction=\"{}\" solref=\"{}\" "
        "solimp=\"{}\" margin=\"{:.17g}\" gap=\"{:.17g}\"/>\n",
        n1, n2, condim, num(friction, 5), num(solref, mjNREF), num(solimp, mjNIMP), margin, gap);
  }
  return x;
}

}  // namespace

std::string build_world_mjcf(const field::Field& f, const WorldOptions& o) {
  return world_mjcf(f, o, "");
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
    // The same contacts from predefined pairs only (the hole's ground filter is then done by
    // update_ground_contact, see there).
    mjcf_ = world_mjcf(field_, options_, predefined_pairs(model_.get()));
    model_ = compile_mjcf(mjcf_);
  }

  mjModel* m = model_.get();
  ids_.ball_body = mj_name2id(m, mjOBJ_BODY, "ball");
  ids_.ball_geom = mj_name2id(m, mjOBJ_GEOM, "ball");
  const int ball_joint = mj_name2id(m, mjOBJ_JOINT, "ball");
  ids_.ball_qpos = m->jnt_qposadr[ball_joint];
  ids_.ball_dof = m->jnt_dofadr[ball_joint];
  ids_.ground_geom = mj_name2id(
      m, mjOBJ_GEOM, options_.ground == GroundContact::kHeightfield ? "lane_surface" : "ground");
  ids_.ground_mocap = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "ground_contact")];
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

  // One process-wide filter, a pure function of (model, data) that acts only on mjData marked as
  // ours (see userdata layout). Set once: assigning it while other threads step would be a race.
  static std::once_flag filter_once;
  std::call_once(filter_once, [] { mjcb_contactfilter = hole_contact_filter; });
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
  d->userdata[kUserMagic] = kMagic;
  d->userdata[kUserBallGeom] = ids_.ball_geom;
  d->userdata[kUserGroundGeom] = ids_.ground_geom;
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
}

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
  // Over the hole opening there is no ground: the contact filter's rule (the ball's centre
  // within the hole's radius), applied here because predefined pairs bypass the filter.
  const double hx = c[0] - d->userdata[kUserHoleX], hy = c[1] - d->userdata[kUserHoleY];
  const double hr = d->userdata[kUserHoleRadius];
  if (options_.ground == GroundContact::kTangentPlane && hx * hx + hy * hy < hr * hr)
    pos[2] -= 10.0;
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
