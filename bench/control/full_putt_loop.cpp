// N full-system putts (the shipped hole's sinking shot, a new angle each: base + 1e-6 rad * i) in
// one of the modes of bench_full_putt. Used by full_putt_instructions.sh to count instructions
// with callgrind (repeatable on a shared machine). Usage: full_putt_loop FIELD MODE N
//   MODE: before (no ball world, no scratch) | exact (default path: ball world, scratch) |
//         repeat (exact, one angle) | kinematic | at-rest | ball (ball-only putts, 2 m/s)
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "sim_backend/full_system.hpp"

int main(int argc, char** argv) {
  using namespace mg;
  if (argc != 4) {
    std::fprintf(stderr, "usage: full_putt_loop FIELD MODE N\n");
    return 2;
  }
  const std::string field = argv[1], mode = argv[2];
  const int n = std::atoi(argv[3]);
  double angle = 0.01, speed = 1.6;
  if (field == "multiple-hills") speed = 1.8;
  if (field == "regular-hill") speed = 1.65;
  if (field == "arctan") angle = 0.03, speed = 1.65;
  const sim::World world = control::make_world_with_arm(field::load_field(field));
  const sim::World ball_world = control::make_ball_world(world);
  const control::ModuleModel model =
      control::make_module_model(world,
                                 ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                                        "/data/models/hitting-default.json"),
                                 control::ModuleConfig{});
  auto d = world.make_data();
  auto bd = ball_world.make_data();
  control::PuttScratch scratch;
  control::FullPuttOptions o;
  if (mode != "before") o.ball_world = &ball_world;
  if (mode == "kinematic") o.rest_start = control::RestStart::kKinematicApproach;
  if (mode == "at-rest") o.rest_start = control::RestStart::kAtRestPose;
  long steps = 0;
  for (int i = 0; i < n; ++i) {
    if (mode == "ball") {
      sim::PuttRequest q;
      q.angle = 0.05;
      q.speed = 2.0;
      steps += sim::simulate_putt(ball_world, bd.get(), ball_world.field().hole.position, q).steps;
      continue;
    }
    const double a = angle + (mode == "repeat" ? 0.0 : 1e-6 * i);
    const auto r = control::full_system_putt(world, model, d.get(), world.field().hole.position, a,
                                             speed, o, mode == "before" ? nullptr : &scratch);
    steps += r.arm_steps;
  }
  std::printf("%ld\n", steps);
  return 0;
}
