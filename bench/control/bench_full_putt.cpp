// Full-system putts (the arm hits the ball, control::full_system_putt) and ball-only putts per
// second per core on each shipped field, and a bare mj_step loop on the arm's model for the same
// number of physics steps as one full-system putt (the floor of what a putt can cost).
//
// FullPutt: the default (exact) path with a ball world and a per-thread scratch: the simulated
// approach, the hit, the roll handed off to the ball-only world. Every iteration uses a new
// hitting angle (base + 1e-6 rad per iteration), as a teacher or an evaluation does, so the
// scratch's approach cache never hits. FullPuttRepeat: one angle (the cache hits).
// FullPuttKinematic / FullPuttAtRest: the opt-in rest starts (not bit-identical, notes/speed.md).
// FullPuttBefore: no ball world, no scratch (the arm simulated to the end, as before).
//
// Run: ./build/bench/control/bench_full_putt   (add --benchmark_format=json for machines)
#include <array>
#include <string>
#include <utility>

#include <benchmark/benchmark.h>

#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "sim/putt.hpp"
#include "sim_backend/full_system.hpp"

namespace {

using namespace mg;

struct Shot {
  const char* field;
  double angle;  ///< [rad] the shipped hole's sinking putt (docs/control.md)
  double speed;  ///< [m/s] club speed
};
constexpr std::array<Shot, 4> kShots{{{"flat", 0.01, 1.6},
                                      {"multiple-hills", 0.01, 1.8},
                                      {"regular-hill", 0.01, 1.65},
                                      {"arctan", 0.03, 1.65}}};

struct Rig {
  sim::World world;
  sim::World ball_world;
  control::ModuleModel model;
  sim::DataPtr d;
  explicit Rig(const std::string& field)
      : world(control::make_world_with_arm(field::load_field(field))),
        ball_world(control::make_ball_world(world)),
        model(
            control::make_module_model(world,
                                       ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                                              "/data/models/hitting-default.json"),
                                       control::ModuleConfig{})),
        d(world.make_data()) {}
};

/// How a benchmark runs its putts.
enum class Mode {
  kExact,      ///< the default approach, hand-off to the ball world, a scratch (new angles: misses)
  kRepeat,     ///< the same, one angle for every putt (the scratch's approach cache hits)
  kKinematic,  ///< RestStart::kKinematicApproach, hand-off, a scratch
  kAtRest,     ///< RestStart::kAtRestPose, hand-off, a scratch
  kBefore,     ///< the approach and the arm to the end, no scratch (as before the speed work)
};

void BM_FullPutt(benchmark::State& state, Shot shot, Mode mode) {
  Rig rig(shot.field);
  const auto hole = rig.world.field().hole.position;
  control::FullPuttOptions options;
  control::PuttScratch scratch;
  if (mode != Mode::kBefore) options.ball_world = &rig.ball_world;
  if (mode == Mode::kKinematic) options.rest_start = control::RestStart::kKinematicApproach;
  if (mode == Mode::kAtRest) options.rest_start = control::RestStart::kAtRestPose;
  control::PuttScratch* use_scratch = mode == Mode::kBefore ? nullptr : &scratch;
  const double angle_step = mode == Mode::kRepeat ? 0.0 : 1e-6;
  long steps = 0, i = 0, sunk = 0, handed_off = 0;
  for (auto _ : state) {
    const double angle = shot.angle + angle_step * static_cast<double>(i++ % 1000);
    const auto r = control::full_system_putt(rig.world, rig.model, rig.d.get(), hole, angle,
                                             shot.speed, options, use_scratch);
    steps += r.arm_steps;
    sunk += r.outcome.sunk ? 1 : 0;
    handed_off += r.handed_off ? 1 : 0;
    benchmark::DoNotOptimize(r.outcome.closest_approach);
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["putts_per_s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.counters["arm_steps_per_putt"] = static_cast<double>(steps) / n;
  state.counters["sunk_fraction"] = static_cast<double>(sunk) / n;
  state.counters["handed_off"] = static_cast<double>(handed_off) / n;
}

// mj_step only, on the arm's model, for as many steps as one full-system putt took before the
// speed work (approach, arm to the end; arm and ball at rest here: no control, no contacts).
void BM_BareArmSteps(benchmark::State& state, Shot shot) {
  Rig rig(shot.field);
  const auto hole = rig.world.field().hole.position;
  control::FullPuttOptions approach;
  approach.rest_start = control::RestStart::kApproach;
  const long steps = control::full_system_putt(rig.world, rig.model, rig.d.get(), hole, shot.angle,
                                               shot.speed, approach)
                         .arm_steps;
  for (auto _ : state) {
    rig.world.reset(rig.d.get());
    for (long k = 0; k < steps; ++k) mj_step(rig.world.model(), rig.d.get());
    benchmark::DoNotOptimize(rig.d->qpos[0]);
  }
  state.counters["steps"] = static_cast<double>(steps);
}

// A ball-only putt (bench/sim/bench_putt's request: 2 m/s at 0.05 rad, ends at rest).
void BM_BallPutt(benchmark::State& state, Shot shot) {
  const sim::World world(field::load_field(shot.field));
  auto d = world.make_data();
  const auto hole = world.field().hole.position;
  sim::PuttRequest q;
  q.angle = 0.05;
  q.speed = 2.0;
  long steps = 0;
  for (auto _ : state) {
    const auto out = sim::simulate_putt(world, d.get(), hole, q);
    steps += out.steps;
    benchmark::DoNotOptimize(out.closest_approach);
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["putts_per_s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.counters["steps_per_putt"] = static_cast<double>(steps) / n;
}

void register_all() {
  for (const Shot& s : kShots) {
    const std::string f = s.field;
    const std::array<std::pair<const char*, Mode>, 5> modes{
        {{"FullPutt/", Mode::kExact},
         {"FullPuttRepeat/", Mode::kRepeat},
         {"FullPuttKinematic/", Mode::kKinematic},
         {"FullPuttAtRest/", Mode::kAtRest},
         {"FullPuttBefore/", Mode::kBefore}}};
    for (const auto& [name, mode] : modes)
      benchmark::RegisterBenchmark((name + f).c_str(), BM_FullPutt, s, mode)
          ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BareArmSteps/" + f).c_str(), BM_BareArmSteps, s)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BallPutt/" + f).c_str(), BM_BallPutt, s)
        ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
