// Ball-only putts per second per core on each shipped field, and the overhead of our putt loop
// (rolling resistance, tangent-plane ground, outcome tracking) over a bare mj_step loop on the
// same model for the same number of steps.
//
// Run: ./build/bench/sim/bench_putt   (add --benchmark_format=json for machines)
#include <array>
#include <string>

#include <benchmark/benchmark.h>

#include "field/field.hpp"
#include "sim/putt.hpp"

namespace {

using mg::sim::PuttRequest;

// A putt that ends at rest short of the hole: the typical data-collection case.
PuttRequest typical_request() {
  PuttRequest q;
  q.angle = 0.05;
  q.speed = 2.0;
  return q;
}

void BM_Putt(benchmark::State& state, const std::string& field_name) {
  const mg::sim::World world(mg::field::load_field(field_name));
  auto d = world.make_data();
  const auto hole = world.field().hole.position;
  long steps = 0;
  for (auto _ : state) {
    const auto out = mg::sim::simulate_putt(world, d.get(), hole, typical_request());
    steps += out.steps;
    benchmark::DoNotOptimize(out.closest_approach);
  }
  state.counters["putts_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["steps_per_putt"] =
      static_cast<double>(steps) / static_cast<double>(state.iterations());
  state.counters["sim_steps_per_s"] =
      benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
}

// The same number of steps as a typical putt with only what the model needs to have ground at
// all (the tangent-plane update) and mj_step: no rolling resistance, no outcome tracking.
void BM_BareStep(benchmark::State& state, const std::string& field_name) {
  const mg::sim::World world(mg::field::load_field(field_name));
  auto d = world.make_data();
  const auto hole = world.field().hole.position;
  const int steps = mg::sim::simulate_putt(world, d.get(), hole, typical_request()).steps;
  long total = 0;
  for (auto _ : state) {
    world.reset(d.get());
    d->qvel[world.ids().ball_dof] = 2.0;
    for (int i = 0; i < steps; ++i) {
      world.update_ground_contact(d.get());
      mj_step(world.model(), d.get());
    }
    total += steps;
    benchmark::DoNotOptimize(d->qpos[0]);
  }
  state.counters["sim_steps_per_s"] =
      benchmark::Counter(static_cast<double>(total), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK_CAPTURE(BM_Putt, flat, std::string("flat"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BareStep, flat, std::string("flat"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Putt, multiple_hills, std::string("multiple-hills"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BareStep, multiple_hills, std::string("multiple-hills"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Putt, regular_hill, std::string("regular-hill"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BareStep, regular_hill, std::string("regular-hill"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Putt, arctan, std::string("arctan"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BareStep, arctan, std::string("arctan"))->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
