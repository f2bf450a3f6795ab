// study adaptation --field F --model NOMINAL.json [--plants 10] [--plant-seed 1]
//   [--checkpoints 0,1,2,3,5,10] [--situations 100] [--learner adapt] [-o CSV] [--json]
// A nominal-simulator model on seeded random plants, before and after a few own putts
// (experiments/adaptation.hpp): a Markdown table (or --json) on stdout, one CSV row per plant and
// checkpoint with -o.
#include <cmath>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/adaptation.hpp"
#include "experiments/evaluate.hpp"
#include "system/system.hpp"

namespace mg::cli {

void add_adaptation_command(CLI::App& app) {
  struct Args {
    std::string field = "flat", config, hitting_model, model, learner = "adapt", out;
    std::vector<std::string> plants_given;
    experiments::AdaptationOptions o;
    bool json = false, no_oracle = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* study = app.get_subcommand("study");
  CLI::App* cmd = study->add_subcommand(
      "adaptation",
      "A nominal model on random plants, before and after a few of the robot's own putts there");
  cmd->add_option("--field", a->field, "Shipped field name or path (the robot's belief)")
      ->capture_default_str();
  cmd->add_option("--config", a->config, "Module config YAML");
  cmd->add_option("--hitting-model", a->hitting_model,
                  "Hitting DS model file (default: the shipped one)");
  cmd->add_option("--model", a->model,
                  "The nominal learner model (trained in the robot's own model of the world)")
      ->required();
  cmd->add_option("--plants", a->o.plants,
                  "Random plants: plant k is `plant random --seed PLANT_SEED+k`")
      ->capture_default_str();
  cmd->add_option("--plant-seed", a->o.plant_seed, "Seed of the plants")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--plant", a->plants_given, "Plant files instead of random plants (repeatable)");
  add_list_option(cmd, "--checkpoints", a->o.checkpoints,
                  "Adaptation putts, increasing, comma-separated (0: the nominal model)",
                  unsigned_integer(kMaxCheckpoint));
  cmd->add_option("--situations", a->o.situations, "Test situations per checkpoint")
      ->capture_default_str();
  cmd->add_option("--seed", a->o.seed, "Seed of the adaptation runs")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--test-seed", a->o.test_seed, "Seed of the test situations")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--learner", a->learner, "adapt | adapt-play | append | self-teach")
      ->capture_default_str();
  cmd->add_option("--threads", a->o.threads, "Threads (0: all cores; results do not depend on it)")
      ->check(CLI::Range(0, 256));
  cmd->add_flag("--no-oracle", a->no_oracle, "Skip the plants' oracle ceilings");
  cmd->add_flag(
      "--no-revise", [a](std::int64_t) { a->o.revise = false; },
      "The robot keeps its belief (it otherwise revises it from every adaptation putt)");
  cmd->add_option("-o,--output", a->out, "CSV to write (one row per plant and checkpoint)")
      ->check(output_file());
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->callback([a] {
    a->o.learner = experiments::parse_curve_learner(a->learner);
    a->o.oracle = !a->no_oracle;
    for (const auto& p : a->plants_given) a->o.given.push_back(plant::load_plant(p));
    a->o.validate();
    auto model = std::make_shared<learning::Model>(learning::load_model(a->model));
    experiments::check_playable_model(*model, a->model);
    if (a->o.learner == experiments::CurveLearner::kAppend &&
        (model->method != learning::Method::kGpr || model->prior))
      throw InputError(fmt::format(
          "--learner append: needs a plain GPR model ({} keeps no data to append to)", a->model));
    const control::ModuleConfig config = system::load_config(a->config, a->field, a->hitting_model);
    const field::Field field = field::load_field(config.field);
    const int plants = a->o.given.empty() ? a->o.plants : static_cast<int>(a->o.given.size());
    Progress bar("adaptation", plants);
    const auto rows = experiments::adaptation_study(config, model, field.situations, a->o,
                                                    [&](int done, int) { bar.update(done); });
    bar.finish();
    if (!a->out.empty()) write_file_atomic(a->out, experiments::adaptation_csv(rows, a->o.learner));
    const auto s = experiments::summarize_adaptation(rows);
    const auto num = [](double v) {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
    };
    if (a->json) {
      nlohmann::json cps = nlohmann::json::array();
      for (std::size_t k = 0; k < s.putts.size(); ++k)
        cps.push_back({{"putts", s.putts[k]},
                       {"median", s.median[k]},
                       {"q10", s.q10[k]},
                       {"q90", s.q90[k]},
                       {"worst", s.worst[k]},
                       {"of_ceiling_median", num(s.of_ceiling_median[k])},
                       {"of_ceiling_worst", num(s.of_ceiling_worst[k])},
                       {"plants_at_goal", s.plants_at_goal[k]}});
      nlohmann::json per = nlohmann::json::array();
      for (const auto& r : rows)
        per.push_back({{"plant", r.index},
                       {"hash", r.plant.hash},
                       {"sunk", r.sunk},
                       {"oracle_found",
                        r.oracle_found >= 0 ? nlohmann::json(r.oracle_found) : nlohmann::json()}});
      fmt::print("{}\n", nlohmann::json{{"field", field.name},
                                        {"model", a->model},
                                        {"learner", a->learner},
                                        {"plants", plants},
                                        {"situations", a->o.situations},
                                        {"checkpoints", cps},
                                        {"per_plant", per}}
                             .dump());
      return;
    }
    fmt::print(
        "| {} on {} ({} plants, {} situations) | median | 10-90 % | worst | of ceiling: median | "
        "worst | plants >= 95 % |\n",
        a->learner, field.name, plants, a->o.situations);
    fmt::print("|---|---|---|---|---|---|---|\n");
    for (std::size_t k = 0; k < s.putts.size(); ++k)
      fmt::print("| {} putts | {:.1f} % | {:.1f}-{:.1f} % | {:.1f} % | {} | {} | {} of {} |\n",
                 s.putts[k], 100 * s.median[k], 100 * s.q10[k], 100 * s.q90[k], 100 * s.worst[k],
                 std::isfinite(s.of_ceiling_median[k])
                     ? fmt::format("{:.1f} %", 100 * s.of_ceiling_median[k])
                     : "-",
                 std::isfinite(s.of_ceiling_worst[k])
                     ? fmt::format("{:.1f} %", 100 * s.of_ceiling_worst[k])
                     : "-",
                 s.plants_at_goal[k], plants);
  });
}

}  // namespace mg::cli
