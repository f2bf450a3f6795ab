// adaptation_cost [PUTTS] [REPEATS]: CPU time per adaptation putt, on each shipped field
// with the GPR model of its shipped data set as the nominal prior, on `plant random --seed 1`:
// self-teach --prior (the robot chooses targets) and evaluate --learn (random situations), each
// PUTTS putts (default 10), REPEATS times (default 3). The learning share is the total minus the
// same putts replayed without learning. Prints a Markdown table (medians over the repeats).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "core/io.hpp"
#include "experiments/evaluate.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"
#include "plant/plant.hpp"
#include "selfteach/self_teach.hpp"
#include "system/system.hpp"

namespace {

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mg;
  const int putts = argc > 1 ? std::atoi(argv[1]) : 10;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 3;
  if (putts < 1 || repeats < 1) {
    std::fprintf(stderr, "usage: adaptation_cost [PUTTS >= 1] [REPEATS >= 1]\n");
    return 2;
  }
  std::printf(
      "| field | self-teach --prior: CPU per putt | evaluate --learn: CPU per putt | of which "
      "learning |\n");
  std::printf("|---|---|---|---|\n");
  for (const std::string name : {"flat", "multiple-hills", "regular-hill", "arctan"}) {
    const learning::Dataset d = learning::load_dataset(data_dir() / "datasets" / (name + ".csv"));
    const auto prior =
        std::make_shared<const learning::Model>(learning::train(d, learning::TrainOptions{}));
    const system::System sys(system::load_config("", name), plant::random_plant(1));
    const auto& region = sys.field().situations;
    std::vector<double> teach, learn, plain;
    for (int r = 0; r < repeats; ++r) {
      selfteach::SelfTeachOptions so;
      so.budget = putts;
      so.threads = 1;
      so.seed = static_cast<std::uint64_t>(r + 1);
      so.prior = prior;
      double t0 = cpu_seconds();
      (void)selfteach::self_teach(sys, region, so);
      teach.push_back((cpu_seconds() - t0) / putts);
      experiments::EvaluateOptions eo;
      eo.situations = putts;
      eo.seed = static_cast<std::uint64_t>(r + 1);
      eo.threads = 1;
      eo.oracle = false;
      eo.teacher.strategy = teacher::parse_strategy(region.strategy);
      t0 = cpu_seconds();
      (void)experiments::evaluate_learning(sys, *prior, region, eo);
      learn.push_back((cpu_seconds() - t0) / putts);
      t0 = cpu_seconds();
      (void)experiments::evaluate_model(sys, *prior, region, eo);
      plain.push_back((cpu_seconds() - t0) / putts);
    }
    std::printf("| %s | %.1f ms | %.1f ms | %.1f ms |\n", name.c_str(), 1e3 * median(teach),
                1e3 * median(learn), 1e3 * (median(learn) - median(plain)));
    std::fflush(stdout);
  }
  return 0;
}
