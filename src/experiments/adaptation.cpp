#include "experiments/adaptation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "experiments/evaluate.hpp"
#include "system/distributed.hpp"
#include "system/parallel.hpp"
#include "system/system.hpp"

namespace mg::experiments {

void AdaptationOptions::validate() const {
  system::check_threads(threads);
  if (given.empty() && (plants < 1 || plants > 1000))
    throw InputError(fmt::format("adaptation: plants: expected 1..1000, got {}", plants));
  if (situations < 1 || situations > 100000)
    throw InputError(fmt::format("adaptation: situations: expected 1..100000, got {}", situations));
  if (learner == CurveLearner::kTeacherGpr || learner == CurveLearner::kCrkr)
    throw InputError("adaptation: learner: expected adapt, adapt-play, append or self-teach");
  CurveOptions c;
  c.checkpoints = checkpoints;
  c.validate();
}

namespace {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace

std::vector<PlantAdaptation> adaptation_study(const control::ModuleConfig& config,
                                              std::shared_ptr<const learning::Model> prior,
                                              const field::Situations& region,
                                              const AdaptationOptions& options,
                                              const std::function<void(int, int)>& progress) {
  options.validate();
  if (!prior) throw InputError("adaptation: needs a nominal model");
  check_playable_model(*prior, "nominal model");
  const field::Field belief = field::load_field(config.field);
  region.validate(belief, "adaptation region");
  std::vector<plant::Plant> plants = options.given;
  if (plants.empty())
    for (int k = 0; k < options.plants; ++k)
      plants.push_back(plant::random_plant(options.plant_seed + static_cast<std::uint64_t>(k)));
  // Every plant's holes before the first plant's putts (a plant that moves a test hole off the
  // lane was found after the other plants had run).
  const auto tests = region.sample_situations(belief, options.situations, options.test_seed);
  std::vector<std::array<double, 2>> holes = region.corners();
  for (const auto& t : tests) holes.push_back(t.hole);
  for (std::size_t k = 0; k < plants.size(); ++k)
    system::check_real_holes(belief, plants[k], holes, fmt::format("adaptation: plant {}", k));
  const system::System nominal(config, belief);
  // Per plant: [oracle_found, sunk at each checkpoint...] (system/wire.hpp sends int vectors).
  std::vector<std::vector<int>> results(plants.size());
  int done = 0;
  system::distributed_for(
      nominal, results, system::thread_count(options.threads),
      [&](int k, system::SystemData&) {
        const system::System sys(config, belief, plants[static_cast<std::size_t>(k)]);
        std::vector<int> r;
        if (options.oracle) {
          EvaluateOptions e;
          e.situations = options.situations;
          e.seed = options.test_seed;
          e.threads = 1;
          e.oracle = true;
          e.teacher.strategy = teacher::parse_strategy(region.strategy);
          e.teacher.learn_speed = region.learn_speed;
          e.teacher.fixed_speed = region.speed;
          r.push_back(evaluate_model(sys, *prior, region, e).oracle_found);
        } else {
          r.push_back(-1);
        }
        CurveOptions c;
        c.checkpoints = options.checkpoints;
        c.seeds = 1;
        c.situations = options.situations;
        c.seed = derive_seed(options.seed, static_cast<std::uint64_t>(k));
        c.test_seed = options.test_seed;
        c.threads = 1;
        c.teacher.strategy = teacher::parse_strategy(region.strategy);
        c.teacher.learn_speed = region.learn_speed;
        c.teacher.fixed_speed = region.speed;
        c.prior = prior;
        c.revise = options.revise;
        const auto runs = learning_curves(sys, region, options.learner, c);
        for (int s : runs.front().sunk) r.push_back(s);
        results[static_cast<std::size_t>(k)] = std::move(r);
      },
      [&](int) {
        if (progress) progress(++done, static_cast<int>(plants.size()));
      });
  std::vector<PlantAdaptation> out;
  for (std::size_t k = 0; k < plants.size(); ++k) {
    PlantAdaptation a;
    a.index = static_cast<int>(k);
    a.plant = plants[k];
    a.putts = options.checkpoints;
    a.situations = options.situations;
    a.oracle_found = results[k].front();
    a.sunk.assign(results[k].begin() + 1, results[k].end());
    out.push_back(std::move(a));
  }
  return out;
}

std::string adaptation_csv(const std::vector<PlantAdaptation>& rows, CurveLearner learner) {
  std::string out =
      "plant,learner,putts,sunk,situations,success,oracle_found,oracle_ceiling,of_ceiling\n";
  for (const auto& r : rows)
    for (std::size_t k = 0; k < r.putts.size(); ++k) {
      const double success = static_cast<double>(r.sunk[k]) / r.situations;
      const double ceiling =
          r.oracle_found >= 0 ? static_cast<double>(r.oracle_found) / r.situations : std::nan("");
      out += fmt::format("{},{},{},{},{},{},{},{},{}\n", r.index, to_string(learner), r.putts[k],
                         r.sunk[k], r.situations, success, r.oracle_found, ceiling,
                         r.oracle_found > 0 ? success / ceiling : std::nan(""));
    }
  return out;
}

AdaptationSummary summarize_adaptation(const std::vector<PlantAdaptation>& rows) {
  AdaptationSummary s;
  if (rows.empty()) return s;
  s.putts = rows.front().putts;
  for (std::size_t k = 0; k < s.putts.size(); ++k) {
    std::vector<double> v, c;
    int at_goal = 0;
    for (const auto& r : rows) {
      const double success = static_cast<double>(r.sunk[k]) / r.situations;
      v.push_back(success);
      if (r.oracle_found > 0) {
        c.push_back(success * r.situations / r.oracle_found);
        at_goal += c.back() >= 0.95 ? 1 : 0;
      }
    }
    s.median.push_back(quantile(v, 0.5));
    s.q10.push_back(quantile(v, 0.1));
    s.q90.push_back(quantile(v, 0.9));
    s.worst.push_back(*std::min_element(v.begin(), v.end()));
    s.of_ceiling_median.push_back(quantile(c, 0.5));
    s.of_ceiling_worst.push_back(c.empty() ? std::nan("") : *std::min_element(c.begin(), c.end()));
    s.plants_at_goal.push_back(at_goal);
  }
  return s;
}

}  // namespace mg::experiments
