// Cost of one hitting-DS evaluation (the 500 Hz budget is 2 ms) and of a SEDS fit.
#include <benchmark/benchmark.h>

#include "core/io.hpp"
#include "ds/demonstrations.hpp"
#include "ds/hitting_ds.hpp"
#include "ds/hitting_model.hpp"

namespace {

const mg::ds::HittingModel& model() {
  static const mg::ds::HittingModel m =
      mg::ds::read_hitting_model(mg::data_dir() / "models" / "hitting-default.json");
  return m;
}

void BM_HittingDsVelocity(benchmark::State& state) {
  const auto& m = model();
  mg::ds::HittingDsData data(m);
  data.set_command(
      m, {0.3, 1.8, mg::ds::Modulator::kSine, m.x_star() + Eigen::Vector3d(-0.4, 0.05, 0.15)});
  // Points along a typical approach, both outside and inside the guidance zone.
  Eigen::Vector3d p = m.x_star() + Eigen::Vector3d(-0.4, 0.05, 0.15);
  const Eigen::Vector3d step = (m.x_star() - p) / 64.0;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(mg::ds::hitting_ds_velocity(m, data, p + (i++ & 63) * step));
  }
}
BENCHMARK(BM_HittingDsVelocity);

void BM_Rollout(benchmark::State& state) {
  const auto& m = model();
  mg::ds::RolloutOptions o;
  o.record = false;
  for (auto _ : state)
    benchmark::DoNotOptimize(mg::ds::rollout(
        m,
        {0.2, 1.5, mg::ds::Modulator::kConstant, m.x_star() + Eigen::Vector3d(-0.35, 0.05, 0.12)},
        o));
}
BENCHMARK(BM_Rollout)->Unit(benchmark::kMillisecond);

void BM_FitShippedDemos(benchmark::State& state) {
  const auto demos = mg::ds::read_demonstrations(mg::data_dir() / "demos" / "default.csv");
  mg::ds::HittingFitOptions opt;
  opt.seds.gaussians = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(mg::ds::fit_hitting_model(demos, opt));
}
BENCHMARK(BM_FitShippedDemos)->Arg(2)->Arg(4)->Arg(6)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
