// Measures the ball physics against the closed forms of PHYSICS.md and prints Markdown tables
// (the numbers of docs/physics.md come from this program).
//
// Run: ./build/bench/sim/physics_report
#include <cmath>
#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "field/field.hpp"
#include "sim/putt.hpp"

namespace {

using namespace mg;
constexpr double kG = 9.81;

field::Field plane(double slope_x, double slope_y, double rho, double depth, double cell) {
  return field::parse_field(fmt::format(R"(
format_version: 1
name: plane
lane: {{bounds: [-0.3, 3.7, -0.6, 0.6], cell_size: {}}}
tee: [0.0, 0.013]
hole: {{position: [3.4, 0.45], depth: {}}}
rolling_resistance: {}
sliding_friction: 0.3
surface: [{{type: plane, slope_x: {}, slope_y: {}}}]
)",
                                        cell, depth, rho, slope_x, slope_y),
                            "plane.yaml", ".");
}

sim::WorldOptions mode(sim::GroundContact g) {
  sim::WorldOptions o;
  o.ground = g;
  return o;
}

const char* name(sim::GroundContact g) {
  return g == sim::GroundContact::kTangentPlane ? "tangent plane" : "heightfield";
}

void rolling_table() {
  fmt::print("### Flat ground, launch without spin (rho = 0.131, mu = 0.3, 2.5 cm cells)\n\n");
  fmt::print(
      "| ground | v0 [m/s] | distance: Penner [m] | measured [m] | error | stop time: Penner [s] | "
      "measured [s] | error | sideways drift [mm] |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|\n");
  for (auto g : {sim::GroundContact::kTangentPlane, sim::GroundContact::kHeightfield}) {
    const sim::World world(plane(0, 0, 0.131, 0.06, 0.025), mode(g));
    auto d = world.make_data();
    for (double v0 : {0.8, 1.5, 2.3}) {
      sim::PuttRequest q;
      q.speed = v0;
      const auto out = sim::simulate_putt(world, d.get(), world.field().hole.position, q);
      const double v1 = 5.0 / 7.0 * v0, a = 5.0 / 7.0 * 0.131 * kG;
      const double dist = 12.0 * v0 * v0 / (49.0 * 0.3 * kG) + v1 * v1 / (2.0 * a);
      const double time = 2.0 * v0 / (7.0 * 0.3 * kG) + v1 / a;
      const double t = out.duration - sim::OutcomeRules{}.rest_time;
      fmt::print(
          "| {} | {:.1f} | {:.4f} | {:.4f} | {:+.2f} % | {:.3f} | {:.3f} | {:+.2f} % | {:.1f} |\n",
          name(g), v0, dist, out.rest_position[0], 100 * (out.rest_position[0] - dist) / dist, time,
          t, 100 * (t - time) / time, 1000 * (out.rest_position[1] - 0.013));
    }
  }
}

void slide_table() {
  fmt::print("\n### Slide, then roll (v0 = 2 m/s, mu = 0.3)\n\n");
  fmt::print(
      "| ground | t* closed form [s] | measured [s] | error | speed at t*: 5/7 v0 [m/s] | measured "
      "[m/s] |\n|---|---|---|---|---|---|\n");
  for (auto g : {sim::GroundContact::kTangentPlane, sim::GroundContact::kHeightfield}) {
    const sim::World world(plane(0, 0, 0.131, 0.06, 0.025), mode(g));
    auto d = world.make_data();
    sim::PuttRequest q;
    q.speed = 2.0;
    q.record_interval = 0.001;
    const auto out = sim::simulate_putt(world, d.get(), world.field().hole.position, q);
    double t_roll = -1, v_roll = 0;
    for (const auto& s : out.trajectory)
      if (std::hypot(s.vx, s.vy) <= 1.005 * 5.0 / 7.0 * 2.0) {
        t_roll = s.t;
        v_roll = std::hypot(s.vx, s.vy);
        break;
      }
    const double t_star = 2.0 * 2.0 / (7.0 * 0.3 * kG);
    fmt::print("| {} | {:.4f} | {:.4f} | {:+.1f} % | {:.4f} | {:.4f} |\n", name(g), t_star, t_roll,
               100 * (t_roll - t_star) / t_star, 5.0 / 7.0 * 2.0, v_roll);
  }
}

void incline_table() {
  fmt::print(
      "\n### Rolling on an incline (no rolling resistance): acceleration along the fall line\n\n");
  fmt::print(
      "| ground | slope (dz/dx, dz/dy) | (5/7) g sin(slope) [m/s^2] | measured [m/s^2] | error "
      "|\n|---|---|---|---|---|\n");
  for (auto g : {sim::GroundContact::kTangentPlane, sim::GroundContact::kHeightfield})
    for (auto [sx, sy] : {std::pair{0.05, 0.0}, std::pair{0.0, 0.08}, std::pair{0.1, 0.05}}) {
      const sim::World world(plane(sx, sy, 0.0, 0.2, 0.025), mode(g));
      auto d = world.make_data();
      sim::PuttRequest q;
      q.speed = 1.2;
      q.rolling_start = true;
      q.max_duration = 0.6;
      q.record_interval = 0.1;
      const auto out = sim::simulate_putt(world, d.get(), world.field().hole.position, q);
      const auto& a = out.trajectory[1];
      const auto& b = out.trajectory[5];
      const double dt = b.t - a.t, gn = std::hypot(sx, sy), slope = std::atan(gn);
      const double fall[3] = {-sx / gn * std::cos(slope), -sy / gn * std::cos(slope),
                              -std::sin(slope)};
      const double along = (b.vx - a.vx) / dt * fall[0] + (b.vy - a.vy) / dt * fall[1] +
                           (b.vz - a.vz) / dt * fall[2];
      const double expected = 5.0 / 7.0 * kG * std::sin(slope);
      fmt::print("| {} | ({}, {}) | {:.4f} | {:.4f} | {:+.2f} % |\n", name(g), sx, sy, expected,
                 along, 100 * (along - expected) / expected);
    }
}

bool sinks(const sim::World& world, mjData* d, double b, double v) {
  const std::array<double, 2> hole{1.5, 0.0};
  const double R = 0.5 * world.field().hole.diameter;
  sim::PuttRequest q;
  q.speed = v;
  q.rolling_start = true;
  q.start = std::array<double, 2>{hole[0] - std::sqrt(std::max(0.0, R * R - b * b)) - 0.002, b};
  q.max_duration = 1.0;
  return sim::simulate_putt(world, d, hole, q).sunk;
}

void capture_table() {
  fmt::print(
      "\n### Capture speed at the hole (108 mm hole, golf ball, rolling; 0.01 m/s steps)\n\n");
  fmt::print(
      "| hole depth [m] | path offset b [m] | v_cap(b) free fall [m/s] | highest speed that sinks "
      "[m/s] | ratio |\n|---|---|---|---|---|\n");
  for (double depth : {0.06, 0.015, 0.01}) {
    const sim::World world(plane(0, 0, 0.131, depth, 0.05));
    auto d = world.make_data();
    for (double b : {0.0, 0.02, 0.035, 0.045}) {
      double v = 0.05;
      while (v < 4.0 && sinks(world, d.get(), b, v + 0.01)) v += 0.01;
      const double R = 0.054, r = world.field().ball.radius;
      const double vcap = (2 * std::sqrt(R * R - b * b) - r) * std::sqrt(kG / (2 * r));
      fmt::print("| {} | {} | {:.3f} | {:.2f} | {:.2f} |\n", depth, b, vcap, v, v / vcap);
    }
  }
}

}  // namespace

int main() {
  rolling_table();
  slide_table();
  incline_table();
  capture_table();
  return 0;
}
