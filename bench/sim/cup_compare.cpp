// Ball-only putts aimed around each shipped field's hole (and two moved holes), one line each:
// to compare two builds of the cup (notes/speed.md: one mocap body against 24). Deterministic.
// Usage: cup_compare [per-segment] > out.txt; cup_compare geometry (a table of wall tops)
//   (field, hole, angle, speed, sunk, end, rest, closest, steps; WorldOptions::cup kOne by default)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/error.hpp"
#include "field/field.hpp"
#include "sim/putt.hpp"

namespace {

// Per hole: how far the one-body cup's wall tops (centre of each top face) are from the
// per-segment cup's, and the one-body cup's tilt.
void print_geometry() {
  std::printf(
      "| field | hole | tilt [deg] | max wall-top difference [mm] | mean [mm] "
      "|\n|---|---|---|---|---|\n");
  for (const char* name : {"flat", "multiple-hills", "regular-hill", "arctan"}) {
    mg::sim::WorldOptions seg_options;
    seg_options.cup = mg::sim::CupBodies::kPerSegment;
    const mg::sim::World one(mg::field::load_field(name)),
        seg(mg::field::load_field(name), seg_options);
    auto d1 = one.make_data();
    auto d2 = seg.make_data();
    const auto h0 = one.field().hole.position;
    for (const std::array<double, 2> shift :
         {std::array<double, 2>{0.0, 0.0}, {-0.4, 0.25}, {-0.7, -0.2}}) {
      const std::array<double, 2> hole{h0[0] + shift[0], h0[1] + shift[1]};
      try {
        one.set_hole(d1.get(), hole);
        seg.set_hole(d2.get(), hole);
      } catch (const mg::InputError&) {
        continue;
      }
      mj_forward(one.model(), d1.get());
      mj_forward(seg.model(), d2.get());
      const auto top = [](const mjModel* m, const mjData* d, int g) {
        const mjtNum* x = d->geom_xpos + 3 * g;
        const mjtNum* r = d->geom_xmat + 9 * g;
        return x[2] + m->geom_size[3 * g + 2] * r[8];
      };
      double worst = 0.0, sum = 0.0;
      const int n = one.options().hole_segments;
      for (int i = 0; i < n; ++i) {
        const double diff = std::abs(top(one.model(), d1.get(), one.ids().first_wall_geom + i) -
                                     top(seg.model(), d2.get(), seg.ids().first_wall_geom + i));
        worst = std::max(worst, diff);
        sum += diff;
      }
      const mjtNum* r = d1->geom_xmat + 9 * one.ids().first_wall_geom;
      std::printf("| %s | (%.3f, %.3f) | %.2f | %.2f | %.2f |\n", name, hole[0], hole[1],
                  std::acos(std::min(1.0, r[8])) * 180.0 / 3.14159265358979, 1e3 * worst,
                  1e3 * sum / n);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "geometry") {
    print_geometry();
    return 0;
  }
  mg::sim::WorldOptions options;
  if (argc > 1 && std::string(argv[1]) == "per-segment")
    options.cup = mg::sim::CupBodies::kPerSegment;
  std::mt19937 rng(20240611);
  for (const char* name : {"flat", "multiple-hills", "regular-hill", "arctan"}) {
    const mg::sim::World world(mg::field::load_field(name), options);
    auto d = world.make_data();
    const auto& f = world.field();
    const auto h0 = f.hole.position;
    for (const std::array<double, 2> shift :
         {std::array<double, 2>{0.0, 0.0}, {-0.4, 0.25}, {-0.7, -0.2}}) {
      const std::array<double, 2> hole{h0[0] + shift[0], h0[1] + shift[1]};
      try {
        world.set_hole(d.get(), hole);
      } catch (const mg::InputError&) {
        continue;
      }
      const double aim = std::atan2(hole[1] - f.tee[1], hole[0] - f.tee[0]);
      std::uniform_real_distribution<double> da(-0.08, 0.08), speed(0.8, 4.5);
      for (int i = 0; i < 100; ++i) {
        mg::sim::PuttRequest q;
        q.angle = aim + da(rng);
        q.speed = speed(rng);
        const auto o = mg::sim::simulate_putt(world, d.get(), hole, q);
        std::printf("%s %.3f %.3f %.17g %.17g %d %s %.17g %.17g %.17g %d\n", name, hole[0], hole[1],
                    q.angle, q.speed, o.sunk ? 1 : 0, mg::sim::to_string(o.end).c_str(),
                    o.rest_position[0], o.rest_position[1], o.closest_approach, o.steps);
      }
    }
  }
  return 0;
}
