// Cost of the module's real-time updates (budget: one core period, 2 ms; aim < 100 us), and of
// a lockstep session second. Each core-update iteration is one tick of a real hit cycle: the
// benchmark restarts Rest -> Hitting -> Braking whenever the cycle ends (the restart is paused).
#include <benchmark/benchmark.h>

#include <string>

#include "control/minigolf_module.hpp"
#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "robot/wam_model.hpp"
#include "sim_backend/full_system.hpp"
#include "sim_backend/mujoco_arm.hpp"

namespace {

using namespace mg;

struct Rig {
  sim::World world{control::make_world_with_arm(field::load_field("flat"))};
  control::ModuleModel model{
      control::make_module_model(world,
                                 ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                                        "/data/models/hitting-default.json"),
                                 control::ModuleConfig{})};
  sim::DataPtr d{world.make_data()};
  control::ModuleData md{model};
  control::SimIds ids{control::find_sim_ids(world)};
  perception::SimulatorPerception truth{world, d.get()};

  void restart() {
    world.reset(d.get());
    robot::Vector7 q;
    for (int j = 0; j < 7; ++j) q[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
    robot::set_joint_positions(ids.arm, d.get(), q);
    mj_forward(world.model(), d.get());
    control::module_reset(model, md, ids.arm, d.get());
    control::request_rest(model, md, 0.1);
  }
  /// The core tick on the simulated arm: read -> update -> write.
  void core_tick() {
    control::MujocoArm arm(ids.arm, d.get());
    control::control_tick(model, md, arm);
  }
  /// Between ticks: the user update of the cycle (hit once at rest) and the robot update.
  void between_ticks() {
    if (md.state == control::ModuleState::kRest && md.at_rest_pose)
      control::request_hit(model, md, 0.1, 1.0);
    if (md.state == control::ModuleState::kIdle && md.tick > 10) restart();
    if (md.tick % model.config().robot_update_divider == 0)
      control::robot_update(model, md, truth.perceive(d->time));
  }
};

void BM_CoreUpdate(benchmark::State& state) {
  Rig rig;
  rig.restart();
  for (auto _ : state) {
    state.PauseTiming();
    rig.between_ticks();
    state.ResumeTiming();
    rig.core_tick();
    state.PauseTiming();
    rig.world.step(rig.d.get());
    rig.world.step(rig.d.get());
    state.ResumeTiming();
  }
}
BENCHMARK(BM_CoreUpdate);

void BM_RobotUpdateHitting(benchmark::State& state) {
  Rig rig;
  rig.restart();
  while (rig.md.state != control::ModuleState::kHitting) {
    rig.between_ticks();
    rig.core_tick();
    rig.world.step(rig.d.get());
    rig.world.step(rig.d.get());
  }
  const perception::Perceived seen = rig.truth.perceive(rig.d->time);
  for (auto _ : state) {
    control::robot_update(rig.model, rig.md, seen);
    benchmark::DoNotOptimize(rig.md.v_ds);
  }
}
BENCHMARK(BM_RobotUpdateHitting);

/// One simulated second of the full system in lockstep (core + robot updates + 1000 physics
/// steps with the arm): how much faster than real time fast mode runs.
void BM_LockstepSecond(benchmark::State& state) {
  Rig rig;
  rig.restart();
  for (auto _ : state) {
    for (int k = 0; k < 500; ++k) {
      rig.between_ticks();
      rig.core_tick();
      rig.world.step(rig.d.get());
      rig.world.step(rig.d.get());
    }
  }
  state.SetLabel("per simulated second");
}
BENCHMARK(BM_LockstepSecond)->Unit(benchmark::kMillisecond);

}  // namespace
