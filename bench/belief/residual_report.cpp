// residual_report [PLANTS] [PUTTS] [DIR]: what the identified green leaves out (docs/belief.md,
// "Beyond the plant's keys"). Per field (flat, regular-hill, arctan, multiple-hills): PLANTS
// random plants (plant::random_plant(1..PLANTS), default 3) as they are, whose green the belief's
// keys express, and the same plants with three unsurveyed Gaussian bumps or dips (1-3 mm high,
// 0.15-0.35 m wide, drawn over the lane), which no key expresses; and the shipped stand-in. On
// each the robot plays PUTTS identification putts (default 10) from the tee, perceives them with
// the plant's vision error, and fits its belief from all of them (every rolling run). Prints the
// fit's residual against the model (rms along and across the ball's motion, the lag-1
// autocorrelation: about 0 for vision error, near 1 for what the model misses), the rolling
// resistance's error, and for the bumpy plants the mean residual in 0.25 m stretches along x.
// With DIR, each bumpy plant is also written there (<field>-bumps-<k>.yaml) to play on.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "belief/residuals.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/rng.hpp"
#include "experiments/identify.hpp"
#include "plant/plant.hpp"
#include "system/system.hpp"

namespace {

using namespace mg;

double uniform(Rng& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// `plant` with three bumps or dips drawn over the lane between the tee and the far end.
plant::Plant with_bumps(plant::Plant plant, const field::Field& field, std::uint64_t seed) {
  Rng rng(derive_seed(seed, 0x62756d7073ULL));  // "bumps"
  const auto& b = field.bounds;
  for (int i = 0; i < 3; ++i) {
    field::BumpTerm bump;
    bump.center = {uniform(rng, field.tee[0] + 0.4, b[1] - 0.2),
                   uniform(rng, b[2] + 0.2, b[3] - 0.2)};
    const double height = uniform(rng, 0.001, 0.003);
    bump.height = rng() % 2 ? height : -height;
    const double sigma = uniform(rng, 0.15, 0.35);
    bump.sigma = {sigma, sigma};
    plant.field.bumps.push_back(bump);
  }
  plant.validate();
  return plant;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mg;
  const int plants = argc > 1 ? std::atoi(argv[1]) : 3;
  const int putts = argc > 2 ? std::atoi(argv[2]) : 10;
  const std::string dir = argc > 3 ? argv[3] : "";
  if (plants < 1 || putts < 1) {
    std::fprintf(stderr, "usage: residual_report [PLANTS >= 1] [PUTTS >= 1] [DIR]\n");
    return 2;
  }
  const plant::Plant stand_in = plant::load_plant(data_dir() / "plants" / "real-wam.yaml");
  std::string bins;
  std::printf(
      "| field | plant | samples | rms along mm | rms across mm | lag-1 | structured | vision "
      "noise mm | rolling resistance error %% |\n|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string name : {"flat", "regular-hill", "arctan", "multiple-hills"}) {
    const control::ModuleConfig config = system::load_config("", name);
    const field::Field surveyed = field::load_field(name);
    for (int p = 0; p <= 2 * plants; ++p) {
      // 0: the stand-in; 1..plants: random plants; plants+1..2 plants: the same with bumps.
      const int k = p > plants ? p - plants : p;
      plant::Plant plant = p == 0 ? stand_in : plant::random_plant(static_cast<std::uint64_t>(k));
      if (p > plants) {
        plant = with_bumps(plant, surveyed, static_cast<std::uint64_t>(k));
        if (!dir.empty())
          write_file_atomic(dir + "/" + name + "-bumps-" + std::to_string(k) + ".yaml",
                            plant::plant_to_yaml(plant));
      }
      const std::string label = p == 0       ? std::string("stand-in")
                                : p > plants ? "random " + std::to_string(k) + " + bumps"
                                             : "random " + std::to_string(k);
      try {
        const system::System truth(config, plant);
        auto hits =
            experiments::plan_identification(truth, putts, "", static_cast<std::uint64_t>(k));
        experiments::play_identification(truth, hits, plant.perception.noise,
                                         static_cast<std::uint64_t>(k));
        const auto id =
            experiments::identify_belief(config, surveyed, hits, hits.size(), std::nullopt, true);
        const belief::ResidualSummary s = belief::summarize_residuals(id.green);
        const double rho = plant::true_rolling_resistance(surveyed, plant);
        std::printf("| %s | %s | %d | %.2f | %.2f | %.2f | %s | %.2f | %.2f |\n", name.c_str(),
                    label.c_str(), s.samples, 1e3 * s.rms_along, 1e3 * s.rms_across, s.lag1,
                    s.structured ? "yes" : "no", 1e3 * plant.perception.noise,
                    100.0 * (id.green.rolling_resistance / rho - 1.0));
        if (p > plants) {
          bins += "| " + name + " | " + label + " |";
          for (const auto& b : s.bins) {
            char cell[96];
            std::snprintf(cell, sizeof cell, " %.2f-%.2f: %+.1f / %+.1f (%d) |", b.x_from, b.x_to,
                          1e3 * b.along, 1e3 * b.across, b.paths);
            bins += cell;
          }
          bins += "\n";
        }
      } catch (const Error& e) {
        std::printf("| %s | %s | - | - | - | - | - | - | %s |\n", name.c_str(), label.c_str(),
                    e.what());
      }
      std::fflush(stdout);
      std::fprintf(stderr, "%s: %s done\n", name.c_str(), label.c_str());
    }
  }
  std::printf(
      "\nThe bumpy plants' mean residual per 0.25 m of lane along x: along / across the ball's "
      "motion in mm (paths there):\n\n%s",
      bins.c_str());
  return 0;
}
