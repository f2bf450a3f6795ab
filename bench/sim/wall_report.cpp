// Borders and obstacles (sim/walls) over many random ball-only putts in the MuJoCo world: across
// every wall impact the ball's energy (kinetic, spin, potential) must not rise, and the ball must
// stay near the surface away from the cup. Prints a Markdown table (docs/physics.md).
//
// usage: wall_report [--putts N] [--fields a,b] [--seed S]
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/rng.hpp"
#include "field/field.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"

namespace {

using namespace mg;
constexpr double kPi = 3.14159265358979323846;

double energy(const sim::World& world, const mjData* d) {
  const auto& ids = world.ids();
  const mjtNum* q = d->qpos + ids.ball_qpos;
  const mjtNum* v = d->qvel + ids.ball_dof;
  const mjModel* m = world.model();
  const double mass = m->body_mass[ids.ball_body], inertia = m->body_inertia[3 * ids.ball_body];
  return 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
         0.5 * inertia * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]) + mass * 9.81 * q[2];
}

struct Row {
  int putts = 0, impacts = 0, gains = 0;
  double worst_gain = 0.0;                    // [J]
  double worst_relative_gain = 0.0;           // [-]
  double rise_played = 0.0, rise_fast = 0.0;  // [m] launches <= 4 m/s, faster
  double fastest_impact = 0.0;                // [m/s]
  double seconds = 0.0;
};

Row run(const std::string& name, int putts, std::uint64_t seed) {
  const sim::World world(field::load_field(name));
  const field::Field& f = world.field();
  sim::DataPtr d = world.make_data();
  Rng rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Row row;
  const auto start_time = std::chrono::steady_clock::now();
  const double cup = 0.5 * f.hole.diameter + f.ball.radius;
  for (int n = 0; n < putts; ++n) {
    std::array<double, 2> start;
    bool free = false;
    while (!free) {
      start = {f.bounds[0] + 0.03 + (f.bounds[1] - f.bounds[0] - 0.06) * u(rng),
               f.bounds[2] + 0.03 + (f.bounds[3] - f.bounds[2] - 0.06) * u(rng)};
      free = std::hypot(start[0] - f.hole.position[0], start[1] - f.hole.position[1]) > 0.15;
      for (const auto& o : f.obstacles) free = free && o.distance(start) > f.ball.radius + 0.01;
    }
    sim::PuttRequest q;
    q.start = start;
    q.angle = kPi * (2.0 * u(rng) - 1.0);
    q.speed = 0.3 + 9.7 * u(rng);
    sim::start_putt(world, d.get(), f.hole.position, q);
    ++row.putts;
    for (int k = 0; k < 3000; ++k) {
      const double before = energy(world, d.get());
      world.step(d.get());
      const mjtNum* c = d->qpos + world.ids().ball_qpos;
      const mjtNum* v = d->qvel + world.ids().ball_dof;
      if (std::hypot(c[0] - f.hole.position[0], c[1] - f.hole.position[1]) < cup) break;
      const double rise = c[2] - f.ball.radius - f.height(c[0], c[1]);
      double& worst = q.speed <= 4.0 ? row.rise_played : row.rise_fast;
      worst = std::max(worst, rise);
      const double impact = world.wall_impact(d.get());
      if (impact > 0.0) {
        ++row.impacts;
        row.fastest_impact = std::max(row.fastest_impact, impact);
        const double gain = energy(world, d.get()) - before;
        if (gain > 0.0) ++row.gains;
        row.worst_gain = std::max(row.worst_gain, gain);
        row.worst_relative_gain = std::max(row.worst_relative_gain, gain / before);
      }
      if (std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) < 0.005) break;
    }
  }
  row.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  int putts = 10000;
  std::uint64_t seed = 20261207;
  std::vector<std::string> fields{"flat", "bank-shot", "l-shape"};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--putts" && i + 1 < argc) {
      putts = std::atoi(argv[++i]);
    } else if (a == "--seed" && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--fields" && i + 1 < argc) {
      fields.clear();
      std::stringstream ss(argv[++i]);
      for (std::string s; std::getline(ss, s, ',');) fields.push_back(s);
    } else {
      std::fprintf(stderr, "usage: wall_report [--putts N] [--fields a,b] [--seed S]\n");
      return 2;
    }
  }
  std::printf(
      "| field | putts (0.3-10 m/s, any direction) | wall impacts | fastest impact [m/s] | "
      "impacts gaining energy | worst gain [J] (relative) | highest rise, launches <= 4 m/s / "
      "faster [mm] | CPU [s] |\n|---|---|---|---|---|---|---|---|\n");
  for (const auto& name : fields) {
    const Row r = run(name, putts, seed);
    std::printf("| %s | %d | %d | %.2f | %d | %.2g (%.2g) | %.2f / %.2f | %.0f |\n", name.c_str(),
                r.putts, r.impacts, r.fastest_impact, r.gains, r.worst_gain, r.worst_relative_gain,
                1e3 * r.rise_played, 1e3 * r.rise_fast, r.seconds);
    std::fflush(stdout);
  }
  return 0;
}
