// bench_learning_fit DATA.csv METHOD K RESTARTS SEED MODEL_OUT
// Trains like `minigolf train` and prints {"fit_seconds": ...}: the in-process time of
// mg::learning::train alone (no process start-up, CSV parsing or model writing), for the
// comparison with scikit-learn's fit() in learners_vs_sklearn.py.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include <fmt/format.h>

#include "learning/learner.hpp"

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: %s DATA.csv METHOD K RESTARTS SEED MODEL_OUT\n", argv[0]);
    return 2;
  }
  try {
    const mg::learning::Dataset d = mg::learning::load_dataset(argv[1]);
    mg::learning::TrainOptions opt;
    opt.method = mg::learning::parse_method(argv[2]);
    opt.num_gaussians = std::atoi(argv[3]);
    opt.restarts = std::atoi(argv[4]);
    opt.seed = std::strtoull(argv[5], nullptr, 10);
    const auto t0 = std::chrono::steady_clock::now();
    const mg::learning::Model m = mg::learning::train(d, opt);
    const auto t1 = std::chrono::steady_clock::now();
    mg::learning::save_model(m, argv[6]);
    fmt::print("{{\"fit_seconds\": {}}}\n", std::chrono::duration<double>(t1 - t0).count());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_learning_fit: %s\n", e.what());
    return 1;
  }
  return 0;
}
