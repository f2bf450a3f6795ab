// In-process fit and predict times of the learners on the synthetic sloped field used by
// bench/learning/learners_vs_sklearn.py (same map, own seeded noise).
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "learning/learner.hpp"
#include "stats/gmr.hpp"

namespace {

mg::learning::Dataset sloped_field(int n, std::uint64_t seed) {
  mg::Rng rng(seed);
  std::uniform_real_distribution<double> ux(0.5, 3.0), uy(-1.2, 1.2);
  std::normal_distribution<double> na(0.0, 0.02), ns(0.0, 0.03);
  mg::learning::Dataset d;
  d.source = "sloped";
  d.input_names = mg::learning::kDefaultInputs;
  d.output_names = mg::learning::kDefaultOutputs;
  d.inputs.resize(n, 2);
  d.outputs.resize(n, 2);
  for (int i = 0; i < n; ++i) {
    const double x = ux(rng), y = uy(rng), dist = std::hypot(x, y), phi = std::atan2(y, x);
    d.inputs.row(i) << x, y;
    d.outputs.row(i) << phi + 0.25 * std::tanh(dist) * std::cos(phi) + 0.1 * std::sin(2 * y) +
                            na(rng),
        std::sqrt(1.2 * dist + 0.25) + 0.15 * y + 0.05 * std::sin(3 * x) + ns(rng);
  }
  return d;
}

void run_fit(benchmark::State& state, mg::learning::Method method) {
  const int n = static_cast<int>(state.range(0));
  const mg::learning::Dataset d = sloped_field(n, 7);
  mg::learning::TrainOptions opt;
  opt.method = method;
  opt.num_gaussians = n <= 10 ? 2 : 3;
  for (auto _ : state) benchmark::DoNotOptimize(mg::learning::train(d, opt));
}

void BM_FitGpr(benchmark::State& s) { run_fit(s, mg::learning::Method::kGpr); }
void BM_FitGmr(benchmark::State& s) { run_fit(s, mg::learning::Method::kGmr); }
void BM_FitJointGmr(benchmark::State& s) { run_fit(s, mg::learning::Method::kJointGmr); }
BENCHMARK(BM_FitGpr)->Arg(10)->Arg(30)->Arg(50)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitGmr)->Arg(10)->Arg(30)->Arg(50)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitJointGmr)->Arg(10)->Arg(30)->Arg(50)->Unit(benchmark::kMillisecond);

// One GMR conditioning in a hot loop (what the DS does per control tick).
void BM_GmrPredictMean(benchmark::State& state) {
  const mg::learning::Dataset d = sloped_field(50, 8);
  mg::learning::TrainOptions opt;
  opt.method = mg::learning::Method::kJointGmr;
  opt.num_gaussians = static_cast<int>(state.range(0));
  const auto model = mg::learning::train(d, opt);
  const mg::stats::GmrConditioner cond(model.gmms[0], {0, 1}, {2, 3});
  auto ws = cond.make_workspace();
  Eigen::VectorXd x(2), out(2);
  x << 0.3, -0.2;
  for (auto _ : state) {
    cond.predict_mean(x, out, ws);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_GmrPredictMean)->Arg(3)->Arg(8);

}  // namespace
