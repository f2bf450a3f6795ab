// The bits of full-system putts in every mode the putt harness has (the simulated approach with
// and without a hand-off and a scratch, the kinematic and at-rest starts, torque and placement
// noise, the plant's vision, a stance beside a ball off the tee), one line per putt: the final
// arm and ball state, the outcome and the launch as hexadecimal doubles, and an FNV-1a hash of
// the whole qpos/qvel/ctrl. Two builds that print the same lines give the same bits: run it
// before and after a change to the scheduler and `diff` the outputs.
//
//   ./build/bench/control/putt_bits > bits.txt
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "robot/wam_model.hpp"
#include "sim_backend/full_system.hpp"

namespace {

using namespace mg;

std::uint64_t fnv(std::uint64_t h, const double* v, int n) {
  for (int i = 0; i < n; ++i) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v[i], sizeof bits);
    for (int b = 0; b < 8; ++b) {
      h ^= (bits >> (8 * b)) & 0xff;
      h *= 1099511628211ULL;
    }
  }
  return h;
}

void print(const char* name, const sim::World& w, const mjData* d,
           const control::FullPuttResult& r) {
  std::uint64_t h = 1469598103934665603ULL;
  h = fnv(h, d->qpos, w.model()->nq);
  h = fnv(h, d->qvel, w.model()->nv);
  h = fnv(h, d->ctrl, w.model()->nu);
  std::printf(
      "%-22s hit %d refused %d sunk %d end %d rest (%a, %a) closest %a duration %a steps %d "
      "launch (%a, %a) club (%a, %a) arm_steps %ld handed_off %d lag %a rest_time %a hash "
      "%016llx\n",
      name, r.hit, r.hit_refused, r.outcome.sunk, static_cast<int>(r.outcome.end),
      r.outcome.rest_position[0], r.outcome.rest_position[1], r.outcome.closest_approach,
      r.outcome.duration, r.outcome.steps, r.launch.angle, r.launch.speed, r.club.angle,
      r.club.speed, r.arm_steps, r.handed_off, r.hit_detection_lag, r.rest_time,
      static_cast<unsigned long long>(h));
}

}  // namespace

int main() {
  const ds::HittingModel hitting = ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                                          "/data/models/hitting-default.json");
  for (const char* field : {"flat", "regular-hill"}) {
    const sim::World world = control::make_world_with_arm(field::load_field(field));
    const sim::World ball_world = control::make_ball_world(world);
    const control::ModuleModel model =
        control::make_module_model(world, hitting, control::ModuleConfig{});
    auto d = world.make_data();
    control::PuttScratch scratch;
    const auto hole = world.field().hole.position;
    const auto run = [&](const std::string& name, double angle, double speed,
                         control::FullPuttOptions o, bool use_scratch,
                         const control::PlantEffectValues& effects = {}) {
      // The true world's effects: wrappers built here, bound by the harness.
      control::PlantWrappers plant(model, effects, o.seed);
      const auto r = control::full_system_putt(world, model, d.get(), hole, angle, speed, o,
                                               use_scratch ? &scratch : nullptr, plant.effects());
      print((std::string(field) + " " + name).c_str(), world, d.get(), r);
    };
    control::FullPuttOptions plain;
    control::FullPuttOptions handoff;
    handoff.ball_world = &ball_world;
    run("approach", 0.01, 1.6, plain, false);
    run("approach-handoff", 0.02, 1.7, handoff, true);
    run("approach-cached", 0.02, 1.7, handoff, true);  // the approach cache hits
    auto kinematic = handoff;
    kinematic.rest_start = control::RestStart::kKinematicApproach;
    run("kinematic", 0.1, 1.4, kinematic, true);
    auto at_rest = handoff;
    at_rest.rest_start = control::RestStart::kAtRestPose;
    run("at-rest", -0.15, 1.2, at_rest, true);
    auto noise = handoff;
    noise.placement_noise = 0.003;
    noise.seed = 7;
    control::PlantEffectValues torque;
    torque.torque_noise = 0.01;
    run("noise", 0.05, 1.5, noise, true, torque);
    auto vision = handoff;
    vision.record_interval = 0.01;
    control::PlantEffectValues plant;
    plant.perception_latency = 0.03;
    plant.perceived_ball_offset = {0.002, -0.001};
    plant.launch_angle_bias = 0.01;
    plant.club_speed_scale = 0.97;
    run("plant-vision", 0.0, 1.6, vision, true, plant);
    run("refused", 0.9, 1.6, handoff, true);
  }
  // A stance: the base beside a ball off the tee (the module built for the robot's own frame).
  const robot::Stance stance{{0.3, 0.2, 0.0}, 0.1};
  const sim::World home = control::make_world_with_arm(field::load_field("flat"));
  const control::ModuleModel model =
      control::make_module_model(home, hitting, control::ModuleConfig{});
  const sim::World world = control::make_world_with_arm(field::load_field("flat"),
                                                        robot::mount_at(robot::WamMount{}, stance));
  auto d = world.make_data();
  control::FullPuttOptions o;
  o.stance = stance;
  const auto r = control::full_system_putt(world, model, d.get(), world.field().hole.position, 0.05,
                                           1.4, o, nullptr);
  print("flat stance", world, d.get(), r);
  return 0;
}
