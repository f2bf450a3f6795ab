// The MJCF text of a World's model (lane, borders, obstacles, ball, cup, ground contact) and its
// compilation; world.cpp builds Worlds from it.
#include "sim/world_mjcf.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGravity = 9.81;

// Collision groups: static geoms only have a contype, so they never collide with each other
// (mocap cup segments would otherwise collide with each other and the ground); the ball has
// every static group in its conaffinity, and the arm's club head (contype 4, see src/robot).
constexpr int kLaneGroup = 1, kCupGroup = 2, kClubGroup = 4, kNoAffinity = 0;

}  // namespace

double damping_ratio_for_restitution(double e) {
  if (e <= 0.0) return 1.0;
  const double l = std::log(e);
  return -l / std::sqrt(kPi * kPi + l * l);
}

std::string world_mjcf(const field::Field& f, const WorldOptions& o, const std::string& pairs) {
  const auto& b = f.bounds;
  const int ncol = static_cast<int>(std::lround((b[1] - b[0]) / f.cell_size)) + 1;
  const int nrow = static_cast<int>(std::lround((b[3] - b[2]) / f.cell_size)) + 1;
  const auto [z_min, z_max] = field::height_range(f);  // over the same grid
  const double elevation = std::max(z_max - z_min, 1e-4);
  const double cx = 0.5 * (b[0] + b[1]), cy = 0.5 * (b[2] + b[3]);
  const double rx = 0.5 * (b[1] - b[0]), ry = 0.5 * (b[3] - b[2]);
  const double wall_t = f.borders.thickness;
  const double wall_bottom = z_min - 0.05, wall_top = z_max + f.borders.height;
  const double wall_hz = 0.5 * (wall_top - wall_bottom), wall_cz = 0.5 * (wall_top + wall_bottom);
  const double hole_r = 0.5 * f.hole.diameter;
  const double seg_half = hole_r * std::tan(kPi / o.hole_segments) + 0.002;
  const double seg_t = 0.01;
  const bool heightfield = o.ground == GroundContact::kHeightfield;

  std::string x;
  x += fmt::format(
      R"(<mujoco model="minigolf-{}">
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
      f.name, o.timestep, -kGravity, "elliptic", 10, pairs.empty() ? "all" : "predefined",
      kUserSize, nrow, ncol, rx, ry, elevation, cx, cy, cx, cy, z_min, 0, kNoAffinity,
      f.sliding_friction, o.ground_time_constant, f.tee[0], f.tee[1], f.height(f.tee[0], f.tee[1]),
      heightfield ? 0 : kLaneGroup, kNoAffinity, f.sliding_friction, o.ground_time_constant);
  // kHeightfield: the heightfield the ball rolls on is an invisible copy of the drawn one in a
  // mocap body, which update_ground_contact drops out of reach under the hole opening; the
  // borders and obstacles are in the next body. MuJoCo collides body pairs in the order of their
  // ids, so the contacts keep the order they had as geoms of the world body (lane, borders,
  // obstacles; then the cup), and with it the solver's bits.
  if (heightfield)
    x += fmt::format(R"(    <body name="lane_contact" mocap="true" pos="{} {} {}">
      <geom name="lane_contact" type="hfield" hfield="lane" rgba="0 0 0 0" contype="{}"
            conaffinity="{}" condim="3" priority="1" friction="{} 0 0" solref="{} 1"/>
    </body>
    <body name="lane_walls" mocap="true" pos="0 0 0">
)",
                     cx, cy, z_min, kLaneGroup, kNoAffinity, f.sliding_friction,
                     o.ground_time_constant);
  const auto wall = [&](const char* name, double px, double py, double hx, double hy) {
    x += fmt::format(
        R"(    <geom name="{}" type="box" pos="{} {} {}" size="{} {} {}" rgba="0.45 0.3 0.2 1"
          contype="0" conaffinity="0"/>
)",
        name, px, py, wall_cz, hx, hy, wall_hz);
  };
  wall("border_x_min", b[0] - 0.5 * wall_t, cy, 0.5 * wall_t, ry + wall_t);
  wall("border_x_max", b[1] + 0.5 * wall_t, cy, 0.5 * wall_t, ry + wall_t);
  wall("border_y_min", cx, b[2] - 0.5 * wall_t, rx, 0.5 * wall_t);
  wall("border_y_max", cx, b[3] + 0.5 * wall_t, rx, 0.5 * wall_t);
  // Borders and obstacles are drawn here and collided by sim/walls (an impulse with their
  // restitution: MuJoCo's soft contacts created energy). Obstacles: boxes over their footprints,
  // from the borders' bottom to `height` above the highest ground under them.
  for (std::size_t i = 0; i < f.obstacles.size(); ++i) {
    const field::Obstacle& ob = f.obstacles[i];
    const field::Footprint fp = ob.footprint();
    const double top = field::obstacle_top(f, ob);
    x += fmt::format(
        R"(    <geom name="obstacle_{}" type="box" pos="{} {} {}" size="{} {} {}" quat="{} 0 0 {}"
          rgba="0.55 0.35 0.22 1" contype="0" conaffinity="0"/>
)",
        i, fp.center[0], fp.center[1], 0.5 * (top + wall_bottom), fp.half[0], fp.half[1],
        0.5 * (top - wall_bottom), std::cos(0.5 * fp.yaw), std::sin(0.5 * fp.yaw));
  }
  if (heightfield) x += "    </body>\n";
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
  // Static geoms (world, ground box, cup) never touch each other (contype only), but MuJoCo
  // would still test every pair of the world's and the mocap bodies' geoms each step (130
  // pairs, half of all collision work).
  std::vector<std::string> mocap{"ground_contact", "hole"};
  if (heightfield) mocap.insert(mocap.end(), {"lane_contact", "lane_walls"});
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
  if (heightfield) {
    // The lane-ball contact as a predefined pair with the parameters MuJoCo mixes for it (the
    // lane's, by priority): MuJoCo 2.2.2's broadphase reports this body pair twice at times, and
    // would then duplicate its contacts. A predefined pair is collided once, where its body pair
    // falls in the order.
    exclude("lane_contact", "ball");
    x += fmt::format(
        "    <pair geom1=\"lane_contact\" geom2=\"ball\" condim=\"3\" friction=\"{0} {0} 0 0 "
        "0\" solref=\"{1} 1\"/>\n",
        f.sliding_friction, o.ground_time_constant);
  }
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

std::string build_world_mjcf(const field::Field& f, const WorldOptions& o) {
  return world_mjcf(f, o, "");
}

}  // namespace mg::sim
