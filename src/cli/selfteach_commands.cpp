// The learners that spend the robot's own putts:
//
//   self-teach --field F --budget N [--seed S] [--batch B] [--log PUTTS.csv] -o MODEL.json
//   curves --field F --learner self-teach|teacher-gpr|crkr|adapt|adapt-play|append [--seeds N]
//          [--checkpoints 10,25,50] -o CURVES.csv
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "belief/belief.hpp"
#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/perception_args.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/identify.hpp"
#include "experiments/learning_curves.hpp"
#include "experiments/revise.hpp"
#include "learning/learner.hpp"
#include "selfteach/self_teach.hpp"
#include "system/distributed.hpp"
#include "system/parallel.hpp"

namespace mg::cli {
namespace {

void add_self_teach(CLI::App& app) {
  struct Args {
    SystemArgs sys;
    std::string situations, balls, strategy, log, out, prior, belief_out;
    int budget = 0;
    int identify = 0;
    int batch = 1;
    double arrival = 0.0;
    std::uint64_t seed = 1;
    bool no_revise = false;
    PerceptionArgs eyes;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "self-teach", "The robot learns a field from its own putts alone: no teacher, no data set");
  add_system_options(cmd, a->sys);
  cmd->add_option("--budget", a->budget, "Full-system putts it may spend, misses included")
      ->required();
  cmd->add_option("--seed", a->seed, "Seed (candidate targets, GP restarts)")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--batch", a->batch,
                  "Putts chosen together per round and played in parallel (the result depends on "
                  "it, not on --threads)")
      ->capture_default_str();
  cmd->add_option("--situations", a->situations,
                  "Region instead of the field's (as collect --situations)");
  cmd->add_option("--balls", a->balls,
                  "Where the ball lies instead of the field's (as collect --balls): it chooses "
                  "(ball, hole) situations and learns the region's inputs");
  cmd->add_option("--strategy", a->strategy,
                  "min-speed | min-angle (default: the field's situations.strategy)");
  cmd->add_option("--log", a->log, "Also write one CSV row per putt here")->check(output_file());
  cmd->add_option("--arrival-speed", a->arrival,
                  "Ball speed [m/s] to reach the hole with (default: the strategy's)")
      ->check(finite_number(0.0, 2.0));
  cmd->add_option("-o,--output", a->out, "Learner model file to write (as minigolf train)")
      ->check(output_file())
      ->required();
  cmd->add_option(
      "--prior", a->prior,
      "Start from this learner model (learned elsewhere; the result is a residual over it)");
  cmd->add_option("--identify", a->identify,
                  "Spend the first N putts of the budget identifying the world (as `identify`), "
                  "then learn in that belief (docs/belief.md); 0: learn in the given belief")
      ->check(CLI::Range(0, 200))
      ->capture_default_str();
  cmd->add_flag("--no-revise", a->no_revise,
                "With --prior: keep the belief (the robot otherwise revises it from every putt "
                "it plays, as `identify` does, and learns the residual in it)");
  cmd->add_option("--belief-out", a->belief_out,
                  "The belief the model is to be played in (with --identify, or --prior "
                  "revising): the file to write")
      ->check(output_file());
  add_perception_options(cmd, a->eyes);
  cmd->callback([a] {
    if (a->identify > 0 && a->identify >= a->budget)
      throw InputError(fmt::format("--identify: expected fewer putts than --budget ({}), got {}",
                                   a->budget, a->identify));
    const bool revise = !a->prior.empty() && !a->no_revise;
    if (!a->belief_out.empty() && a->identify == 0 && !revise)
      throw InputError(
          "--belief-out: needs --identify or a revising --prior (no belief is identified)");
    if (!a->belief_out.empty()) check_output_file(a->belief_out);
    selfteach::SelfTeachOptions o;
    if (!a->prior.empty()) {
      auto prior = std::make_shared<learning::Model>(learning::load_model(a->prior));
      experiments::check_playable_model(*prior, a->prior);
      o.prior = std::move(prior);
    }
    o.budget = a->budget - a->identify;
    o.batch = a->batch;
    o.seed = a->seed;
    o.threads = a->sys.threads;
    o.arrival_speed = a->arrival;
    o.validate();
    const control::ModuleConfig config =
        system::load_config(a->sys.config, a->sys.field, a->sys.hitting_model);
    const plant::Plant plant = load_plant_arg(a->sys.plant);
    plant::Plant believed = load_belief_arg(a->sys.belief);
    const field::Field lane = field::load_field(config.field);
    const field::Field truth = plant::true_field(lane, plant);
    const system::PerceptionFactory eyes = perception_factory(a->eyes, {&truth});
    // What the robot believes, with its uncertainty: the given belief, then identify's.
    std::optional<belief::Belief> prior;
    if (!a->sys.belief.empty()) prior = belief::load_belief(a->sys.belief);
    if (a->identify > 0) {
      // The belief first: identify's putts, its fit with the given belief as the prior.
      const system::System before(config, lane, plant, believed, eyes);
      Progress id_bar("identify", a->identify);
      const auto id = experiments::identify_world(config, before, a->identify, a->balls, a->seed,
                                                  prior, [&](int k) { id_bar.update(k); });
      id_bar.finish();
      believed = id.belief.estimate;
      prior = id.belief;
      fmt::print(
          "identified the world in {} putts: rolling resistance {:.4g}, slope ({:.2g}, "
          "{:.2g}), club speed scale {:.4g}\n",
          a->identify, plant::true_rolling_resistance(before.survey(), id.belief.estimate),
          id.belief.estimate.field.extra_slope[0], id.belief.estimate.field.extra_slope[1],
          id.belief.estimate.arm.club_speed_scale);
      if (!a->belief_out.empty() && !revise)
        write_file_atomic(a->belief_out, belief::belief_to_yaml(id.belief));
    }
    const system::System sys(config, lane, plant, believed, eyes);
    std::unique_ptr<experiments::BeliefReviser> reviser;
    if (revise) reviser = experiments::revise_hook(sys, o, prior);
    field::Situations region = field::region_from_spec(sys.field(), a->situations, a->balls);
    if (!a->strategy.empty())
      region.strategy = teacher::to_string(teacher::parse_strategy(a->strategy));
    Progress bar("self-teach", o.budget);
    const auto r = selfteach::self_teach(sys, region, o, [&](int done, int) { bar.update(done); });
    bar.finish();
    if (!a->log.empty()) {
      const bool balls = region.balls.has_value();  // the balls' columns (last) only then
      std::string csv =
          "index,target_x,target_y,angle,speed,hit,sunk,closest_approach,launch_angle,launch_speed,"
          "labels,label_distance";
      csv += balls ? ",ball_x,ball_y\n" : "\n";
      for (std::size_t i = 0; i < r.putts.size(); ++i) {
        const auto& p = r.putts[i];
        csv += fmt::format("{},{},{},{},{},{:d},{:d},{},{},{},{},{}", i, p.target[0], p.target[1],
                           p.angle, p.speed, p.hit, p.sunk, p.closest_approach, p.launch_angle,
                           p.launch_speed, p.labels, p.label_distance);
        csv += balls ? fmt::format(",{},{}\n", p.ball[0], p.ball[1]) : "\n";
      }
      write_file_atomic(a->log, csv);
    }
    if (!r.trained)
      throw InputError(fmt::format(
          "self-teach: field '{}': {} hindsight label(s) in the region after {} putts (need "
          "{}): no putt's path crossed the region{}",
          sys.field().name, r.labels.size(), r.putts.size(), o.prior ? 1 : 2,
          a->log.empty() ? "" : fmt::format(" (the putts are in {})", a->log)));
    learning::save_model(r.model, a->out);
    if (reviser) {
      const auto& b = reviser->belief();
      fmt::print(
          "revised its belief {} times (longest {:.2f} s CPU): rolling resistance {:.4g}, slope "
          "({:.2g}, {:.2g}), club speed scale {:.4g}; play the model in it{}\n",
          reviser->revisions(), reviser->max_cpu(),
          plant::true_rolling_resistance(sys.survey(), b.estimate), b.estimate.field.extra_slope[0],
          b.estimate.field.extra_slope[1], b.estimate.arm.club_speed_scale,
          a->belief_out.empty() ? " (--belief-out writes it)" : "");
      if (!a->belief_out.empty()) write_file_atomic(a->belief_out, belief::belief_to_yaml(b));
    }
    fmt::print(
        "self-taught {} in {} full-system putts ({} sank while learning): {} hindsight labels{}; "
        "labels at "
        "their own target sank {} of {}; model written to {}\n",
        sys.field().name, r.putts.size(), r.sunk, r.labels.size(),
        region.learn_speed ? fmt::format(" at arrival speed {:.3g} m/s", r.arrival_speed)
                           : fmt::format(" (angle only at {} m/s)", region.speed),
        r.on_target_sunk, r.on_target, a->out);
  });
}

void add_curves(CLI::App& app) {
  struct Args {
    SystemArgs sys;
    std::string learner = "self-teach", situations_spec, balls, out, prior;
    experiments::CurveOptions o;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "curves", "Learning curves: test success against full-system putts spent, per seed");
  add_system_options(cmd, a->sys);
  cmd->add_option("--learner", a->learner,
                  "self-teach | teacher-gpr | crkr | adapt | adapt-play | append (the last three "
                  "start from --prior)")
      ->capture_default_str();
  cmd->add_option(
      "--prior", a->prior,
      "Learner model to adapt (adapt, adapt-play, append), e.g. trained in the nominal simulator");
  add_list_option(cmd, "--checkpoints", a->o.checkpoints,
                  "Putt counts, increasing, comma-separated", unsigned_integer(kMaxCheckpoint));
  cmd->add_option("--seeds", a->o.seeds, "Runs")->capture_default_str();
  cmd->add_option("--situations", a->o.situations, "Test situations per checkpoint")
      ->capture_default_str();
  cmd->add_option("--seed", a->o.seed, "Seed of the runs")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--test-seed", a->o.test_seed, "Seed of the test situations")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--region", a->situations_spec,
                  "Region instead of the field's (as collect --situations)");
  cmd->add_option("--balls", a->balls,
                  "Where the ball lies (as collect --balls; learners self-teach, adapt and "
                  "teacher-gpr)");
  cmd->add_option("-o,--output", a->out, "CSV to write")->check(output_file())->required();
  cmd->add_flag(
      "--no-revise", [a](std::int64_t) { a->o.revise = false; },
      "adapt, adapt-play, append: keep the belief (they otherwise revise it from every putt)");
  cmd->callback([a] {
    const experiments::CurveLearner learner = experiments::parse_curve_learner(a->learner);
    if (experiments::needs_prior(learner) != !a->prior.empty())
      throw InputError(
          a->prior.empty()
              ? fmt::format("--learner {}: needs --prior MODEL", a->learner)
              : fmt::format("--prior: only with --learner adapt, adapt-play or append"));
    if (!a->prior.empty()) {
      auto prior = std::make_shared<learning::Model>(learning::load_model(a->prior));
      experiments::check_playable_model(*prior, a->prior);
      a->o.prior = std::move(prior);
    }
    if (a->o.prior && learner == experiments::CurveLearner::kAppend &&
        (a->o.prior->method != learning::Method::kGpr || a->o.prior->prior))
      throw InputError(fmt::format(
          "--learner append: needs a plain GPR prior ({} keeps no data to append to)", a->prior));
    a->o.threads = a->sys.threads;
    a->o.validate();
    check_output_file(a->out);  // before minutes of putts, not after
    const system::System sys(system::load_config(a->sys.config, a->sys.field, a->sys.hitting_model),
                             load_plant_arg(a->sys.plant), load_belief_arg(a->sys.belief));
    const field::Situations region =
        field::region_from_spec(sys.field(), a->situations_spec, a->balls);
    a->o.teacher = teacher::options_for(region, "");
    Progress bar("curves", a->o.seeds);
    const auto runs = experiments::learning_curves(sys, region, learner, a->o,
                                                   [&](int done, int) { bar.update(done); });
    bar.finish();
    write_file_atomic(a->out, experiments::curves_csv(runs));
    const auto s = experiments::summarize(runs);
    for (std::size_t k = 0; k < s.putts.size(); ++k)
      fmt::print(
          "{} on {} after {} putts: median {:.1f} % (10-90 %: {:.1f}-{:.1f} %) over {} runs\n",
          a->learner, sys.field().name, s.putts[k], 100 * s.median[k], 100 * s.q10[k],
          100 * s.q90[k], runs.size());
  });
}

}  // namespace

void add_selfteach_commands(CLI::App& app) {
  add_self_teach(app);
  add_curves(app);
}

}  // namespace mg::cli
