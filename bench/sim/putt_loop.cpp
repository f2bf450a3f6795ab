// One ball-only putt, then (mode) nothing, a second putt, or the same number of bare steps.
// Used by putt_overhead.sh to count instructions with callgrind: deterministic, unlike wall time
// on a shared machine. Usage: putt_loop FIELD none|putt|bare
#include <cstdio>
#include <string>

#include "field/field.hpp"
#include "sim/putt.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: putt_loop FIELD none|putt|bare\n");
    return 2;
  }
  const std::string mode = argv[2];
  const mg::sim::World world(mg::field::load_field(argv[1]));
  auto d = world.make_data();
  mg::sim::PuttRequest q;
  q.angle = 0.05;
  q.speed = 2.0;
  const auto hole = world.field().hole.position;
  const int steps = mg::sim::simulate_putt(world, d.get(), hole, q).steps;
  if (mode == "putt") {
    mg::sim::simulate_putt(world, d.get(), hole, q);
  } else if (mode == "bare") {
    world.reset(d.get());
    d->qvel[world.ids().ball_dof] = q.speed;
    for (int i = 0; i < steps; ++i) {
      world.update_ground_contact(d.get());
      mj_step(world.model(), d.get());
    }
  }
  std::printf("%d\n", steps);
  return 0;
}
