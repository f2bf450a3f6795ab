// The robot plays: sweep (sinking windows), collect (the teacher's data sets), evaluate (the
// learned model on random test situations, thesis table 6.5), reproduce (chapter 6). All run
// putts on every core. The learners that spend their own putts: selfteach_commands.cpp.
//
//   sweep --field F [--hole X,Y] --angles A0:A1:N --speeds V0:V1:N [--ball-only] -o OUT.csv
//         [--plot OUT.png]
//   collect --field F [--strategy S] [--situations SPEC] [--seed S] [--resume] -o DATA.csv
//   evaluate --field F --model M [--situations N] [--seed S] [--no-oracle] [--json] [-o ROWS.csv]
//   reproduce [--quick] [--fields F,...] [-o DIR]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
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
#include "experiments/collect.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/learning_curves.hpp"
#include "experiments/reproduce.hpp"
#include "experiments/sweep.hpp"
#include "learning/learner.hpp"
#include "selfteach/self_teach.hpp"
#include "system/distributed.hpp"
#include "system/parallel.hpp"

namespace mg::cli {
namespace {

/// "A0:A1:N" -> N values from A0 to A1 inclusive.
std::vector<double> parse_range(const std::string& what, const std::string& text) {
  const auto a = text.find(':'), b = text.rfind(':');
  if (a == std::string::npos || a == b)
    throw InputError(fmt::format("{}: expected LO:HI:N, got '{}'", what, text));
  const double lo = parse_number(what, text.substr(0, a));
  const double hi = parse_number(what, text.substr(a + 1, b - a - 1));
  const std::uint64_t n = parse_unsigned(what, text.substr(b + 1));
  if (n < 1 || n > 1000)
    throw InputError(fmt::format("{}: expected N in 1..1000, got {}", what, n));
  if (hi < lo) throw InputError(fmt::format("{}: expected LO <= HI, got {}:{}", what, lo, hi));
  return experiments::linspace(lo, hi, static_cast<int>(n));
}

void add_sweep(CLI::App& app) {
  struct Args {
    SystemArgs sys;
    std::string hole, angles, speeds, out, plot;
    bool ball_only = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "sweep", "Outcome of every (angle, speed) cell of a grid: the sinking window");
  add_system_options(cmd, a->sys);
  cmd->add_option("--hole", a->hole, "Hole centre X,Y [m] (default: the field's)");
  cmd->add_option("--angles", a->angles, "A0:A1:N hitting angles [rad] (ball only: launch angles)")
      ->required();
  cmd->add_option("--speeds", a->speeds, "V0:V1:N club speeds [m/s] (ball only: launch speeds)")
      ->required();
  cmd->add_flag("--ball-only", a->ball_only, "Launch the ball directly (no arm)");
  cmd->add_option("-o,--output", a->out, "CSV file to write")->check(output_file())->required();
  cmd->add_option("--plot", a->plot, "Also draw a heat map PNG here")->check(output_file());
  cmd->callback([a] {
    experiments::SweepOptions o;
    o.angles = parse_range("--angles", a->angles);
    o.speeds = parse_range("--speeds", a->speeds);
    o.ball_only = a->ball_only;
    o.threads = a->sys.threads;
    check_output_file(a->out);  // before the sweep, not after it
    if (!a->plot.empty()) check_output_file(a->plot);
    const system::System sys(system::load_config(a->sys.config, a->sys.field, a->sys.hitting_model),
                             load_plant_arg(a->sys.plant), load_belief_arg(a->sys.belief));
    if (!a->ball_only)
      for (double angle : o.angles)
        for (double speed : o.speeds) sys.check_request(angle, speed, "sweep");
    o.hole = a->hole.empty() ? sys.field().hole.position : parse_vector<2>("--hole", a->hole);
    Progress bar("sweep", static_cast<int>(o.angles.size() * o.speeds.size()));
    const auto cells = experiments::run_sweep(sys, o, [&](int done, int) { bar.update(done); });
    bar.finish();
    write_file_atomic(a->out, experiments::sweep_csv(cells));
    int sunk = 0;
    for (const auto& c : cells) sunk += c.outcome.sunk;
    if (!a->plot.empty() && system::is_root_process())  // one process draws (MPI)
      run_plot_script(
          fmt::format("sweep {} {} --title {}", shell_quote(a->out), shell_quote(a->plot),
                      shell_quote(fmt::format("{} hole ({:g}, {:g}){}", sys.field().name, o.hole[0],
                                              o.hole[1], a->ball_only ? ", ball only" : ", arm"))),
          a->plot);
    fmt::print("sweep on {} ({}), hole ({}, {}): {} of {} cells sink; written to {}\n",
               sys.field().name, a->ball_only ? "ball only" : "arm", o.hole[0], o.hole[1], sunk,
               cells.size(), a->out);
  });
}

void add_collect(CLI::App& app) {
  struct Args {
    SystemArgs sys;
    std::string strategy, situations, balls, out;
    std::uint64_t seed = 1;
    bool resume = false;
    int max_full_putts = teacher::TeacherOptions{}.max_full_putts;
    int random = 0;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "collect", "The teacher collects a data set of sinking putts (thesis 5.1)");
  add_system_options(cmd, a->sys);
  cmd->add_option("--strategy", a->strategy,
                  "min-speed | min-angle (default: the field's situations.strategy)");
  cmd->add_option("--situations", a->situations,
                  "Region instead of the field's: line:X0,Y0:X1,Y1:N | grid:X0,X1:Y0,Y1:NX,NY | "
                  "box:... | list:X,Y;X,Y");
  cmd->add_option("--balls", a->balls,
                  "Where the ball lies instead of the field's (the same grammar; default: the "
                  "tee): every ball with every hole (docs/play.md)");
  cmd->add_option("--seed", a->seed, "Seed (recorded; the teacher is deterministic)")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--max-full-putts", a->max_full_putts, "Full-system putt budget per situation")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option(
         "--random", a->random,
         "Collect at N random situations of the region (seeded by --seed) instead of its points")
      ->check(CLI::Range(0, 100000));
  cmd->add_flag("--resume", a->resume, "Continue an interrupted collection in the output file");
  cmd->add_option("-o,--output", a->out, "Data set CSV to write")->check(output_file())->required();
  cmd->callback([a] {
    const system::System sys(system::load_config(a->sys.config, a->sys.field, a->sys.hitting_model),
                             load_plant_arg(a->sys.plant), load_belief_arg(a->sys.belief));
    const field::Situations region = field::region_from_spec(sys.field(), a->situations, a->balls);
    experiments::CollectOptions o;
    o.teacher = teacher::options_for(region, a->strategy);
    o.teacher.max_full_putts = a->max_full_putts;
    o.seed = a->seed;
    o.threads = a->sys.threads;
    o.resume = a->resume;
    const auto situations = a->random > 0
                                ? region.sample_situations(sys.field(), a->random, a->seed)
                                : region.collection_situations(sys.field());
    Progress bar("collect", static_cast<int>(situations.size()));
    int full = 0, ball = 0;
    const auto r = experiments::collect(
        sys, situations, o, a->out, [&](int done, int, const teacher::Example& e) {
          full += e.full_putts;
          ball += e.ball_putts;
          bar.update(done, fmt::format("({} full-system, {} ball-only putts)", full, ball));
        });
    bar.finish();
    int found = 0;
    for (const auto& e : r.examples) found += e.found;
    if (found == 0)
      throw InputError(
          fmt::format("collect: no sinking putt in any of the {} situations on {}: the region is "
                      "unplayable (the attempts are recorded in {})",
                      r.examples.size(), sys.field().name, a->out));
    fmt::print(
        "collected {} of {} situations on {} ({}{}; {} resumed, {} replaced by the continuity "
        "pass): {} "
        "full-system and {} ball-only putts; written to {}\n",
        found, r.examples.size(), sys.field().name, teacher::to_string(o.teacher.strategy),
        o.teacher.learn_speed ? "" : fmt::format(", angle only at {} m/s", o.teacher.fixed_speed),
        r.resumed, r.repaired, r.full_putts, r.ball_putts, a->out);
  });
}

void add_evaluate(CLI::App& app) {
  struct Args {
    SystemArgs sys;
    std::string model, situations_spec, balls, rows, strategy, save_model, learn_mode = "residual",
                                                                           belief_out;
    int situations = 30;
    std::uint64_t seed = 1;
    bool json = false, no_oracle = false, learn = false, no_revise = false;
    double perception_noise = 0.0, torque_noise = 0.0;
    PerceptionArgs eyes;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "evaluate", "The robot plays random test situations with a learned model (thesis 6.3)");
  add_system_options(cmd, a->sys);
  cmd->add_option("--model", a->model, "Learner model file (minigolf train)")->required();
  cmd->add_option("--situations", a->situations, "Number of random test situations")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--region", a->situations_spec,
                  "Region instead of the field's (as collect --situations)");
  cmd->add_option("--balls", a->balls,
                  "Where the ball lies instead of the field's (as collect --balls)");
  cmd->add_option("--seed", a->seed, "Seed of the test situations")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--strategy", a->strategy,
                  "The oracle teacher's strategy (default: the field's)");
  cmd->add_flag("--no-oracle", a->no_oracle,
                "Skip the oracle ceiling (the teacher on every situation)");
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->add_option("-o,--output", a->rows, "Also write one CSV row per situation here")
      ->check(output_file());
  cmd->add_flag("--learn", a->learn,
                "Keep learning while playing: each putt's hindsight labels correct the model "
                "(implies --no-oracle)");
  cmd->add_option("--learn-mode", a->learn_mode,
                  "With --learn: residual (the model is a prior, a residual GP learns) | append "
                  "(labels join a GPR model's data)")
      ->capture_default_str();
  cmd->add_option("--save-model", a->save_model, "With --learn: write the model as it ends up here")
      ->check(output_file());
  cmd->add_flag("--no-revise", a->no_revise,
                "With --learn: keep the belief (it is otherwise revised from every putt played, "
                "as `identify` does, and each later putt is planned in it)");
  cmd->add_option("--belief-out", a->belief_out,
                  "With --learn: write the belief the model ends up to be played in")
      ->check(output_file());
  cmd->add_option("--perception-noise", a->perception_noise,
                  "Std [m] of the perceived hole and ball positions, per axis");
  cmd->add_option("--torque-noise", a->torque_noise,
                  "Joint torque noise std, fraction of the limits");
  add_perception_options(cmd, a->eyes);
  cmd->callback([a] {
    if (!a->save_model.empty() && !a->learn) throw InputError("--save-model: only with --learn");
    if (!a->belief_out.empty() && (!a->learn || a->no_revise))
      throw InputError("--belief-out: only with --learn, revising");
    if (a->no_revise && !a->learn) throw InputError("--no-revise: only with --learn");
    const learning::Model model = learning::load_model(a->model);
    const auto config = system::load_config(a->sys.config, a->sys.field, a->sys.hitting_model);
    const plant::Plant plant = load_plant_arg(a->sys.plant);
    field::Field lane = field::load_field(config.field);
    const field::Field truth = plant::true_field(lane, plant);
    system::PerceptionFactory eyes = perception_factory(a->eyes, {&truth});
    const system::System sys(config, std::move(lane), plant, load_belief_arg(a->sys.belief),
                             std::move(eyes));
    experiments::check_playable_model(model, a->model, &sys);
    const field::Situations region =
        field::region_from_spec(sys.field(), a->situations_spec, a->balls);
    experiments::EvaluateOptions o;
    o.situations = a->situations;
    o.seed = a->seed;
    o.threads = a->sys.threads;
    o.oracle = !a->no_oracle;
    o.teacher = teacher::options_for(region, a->strategy);
    o.perception_noise = a->perception_noise;
    o.torque_noise = a->torque_noise;
    if (a->learn) o.oracle = false;
    o.revise = a->learn && !a->no_revise;
    if (o.revise && !a->sys.belief.empty()) o.belief_prior = belief::load_belief(a->sys.belief);
    if (a->learn_mode == "residual")
      o.learn = experiments::LearnMode::kResidual;
    else if (a->learn_mode == "append")
      o.learn = experiments::LearnMode::kAppend;
    else
      throw InputError(
          fmt::format("--learn-mode: expected residual or append, got '{}'", a->learn_mode));
    Progress bar("evaluate", a->situations);
    experiments::Evaluation e;
    std::vector<int> labels_added;
    int revisions = 0;
    double revision_cpu = 0.0;
    if (a->learn) {
      auto le = experiments::evaluate_learning(sys, model, region, o,
                                               [&](int done, int) { bar.update(done); });
      e = std::move(le.evaluation);
      labels_added = std::move(le.labels_added);
      if (!a->save_model.empty()) learning::save_model(le.learned, a->save_model);
      if (!a->belief_out.empty())
        write_file_atomic(a->belief_out, belief::belief_to_yaml(le.belief));
      revisions = le.revisions;
      revision_cpu = le.revision_max_cpu;
    } else {
      e = experiments::evaluate_model(sys, model, region, o,
                                      [&](int done, int) { bar.update(done); });
    }
    bar.finish();
    int first_half = 0, second_half = 0, added = 0;
    for (std::size_t i = 0; i < e.rows.size(); ++i)
      (2 * i < e.rows.size() ? first_half : second_half) += e.rows[i].sunk;
    for (int k : labels_added) added += k;
    if (!a->rows.empty()) write_file_atomic(a->rows, experiments::evaluation_csv(e, sys.field()));
    if (a->json) {
      nlohmann::json rows = nlohmann::json::array();
      for (const auto& r : e.rows)
        rows.push_back(
            {{"hole", r.hole},
             {"ball", r.ball},
             {"angle", r.predicted.angle},
             {"speed", r.predicted.speed},
             {"in_envelope", r.in_envelope},
             {"sunk", r.sunk},
             {"closest_approach",
              r.in_envelope ? nlohmann::json(r.outcome.closest_approach) : nlohmann::json()},
             {"oracle_found", o.oracle ? nlohmann::json(r.oracle_found) : nlohmann::json()}});
      const nlohmann::json j = {
          {"field", sys.field().name},
          {"model", a->model},
          {"method", std::string(learning::method_name(model.method))},
          {"situations", a->situations},
          {"seed", a->seed},
          {"sunk", e.sunk},
          {"success_ratio", e.success_ratio},
          {"ci95", e.ci95},
          {"oracle_ceiling", o.oracle ? nlohmann::json(e.oracle_ceiling) : nlohmann::json()},
          {"oracle_found", o.oracle ? nlohmann::json(e.oracle_found) : nlohmann::json()},
          {"plant", plant_json(sys.plant())},
          {"learn", a->learn},
          {"labels_added", a->learn ? nlohmann::json(labels_added) : nlohmann::json()},
          {"revisions", o.revise ? nlohmann::json(revisions) : nlohmann::json()},
          {"rows", rows}};
      fmt::print("{}\n", j.dump());
      return;
    }
    fmt::print("{} on {}: sunk {} of {} = {:.1f} % (95 % CI {:.1f}-{:.1f} %){}\n",
               learning::method_name(model.method), sys.field().name, e.sunk, a->situations,
               100.0 * e.success_ratio, 100.0 * e.ci95[0], 100.0 * e.ci95[1],
               o.oracle ? fmt::format("; oracle ceiling {:.1f} % ({} of {})",
                                      100.0 * e.oracle_ceiling, e.oracle_found, a->situations)
                        : "");
    if (a->learn)
      fmt::print(
          "learning while playing: {} hindsight labels added; first half sunk {} of {}, second "
          "half {} of {}{}\n",
          added, first_half, (e.rows.size() + 1) / 2, second_half, e.rows.size() / 2,
          o.revise ? fmt::format("; belief revised {} times (longest {:.2f} s CPU)", revisions,
                                 revision_cpu)
                   : "");
  });
}

void add_reproduce(CLI::App& app) {
  auto o = std::make_shared<experiments::ReproduceOptions>();
  auto out = std::make_shared<std::string>("out/reproduce");
  auto datasets = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("reproduce",
                                     "Thesis chapter 6 end to end: data sets, training, MSE, the "
                                     "robot playing, figures, report.md");
  cmd->add_flag(
      "--no-beyond", [o](std::int64_t) { o->beyond = false; },
      "Skip the beyond-the-thesis part (self-teaching, baselines, noise)");
  cmd->add_flag(
      "--quick", o->quick,
      "30 test situations, 3 learning-curve subsets, 100 arctan splits (under 10 min on 2 cores)");
  cmd->add_option("-o,--output", *out, "Output folder")->capture_default_str();
  cmd->add_option("--threads", o->threads, "Threads (0: all cores; results do not depend on it)")
      ->check(CLI::Range(0, 256));
  cmd->add_option("--seed", o->seed, "Seed of test situations, splits and subsets")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_flag("--collect", o->collect,
                "Collect the data sets with the teacher instead of using the shipped ones");
  cmd->add_option("--datasets", *datasets,
                  "Folder with <field>.csv and <field>-validation.csv (default: data/datasets)");
  add_list_option(cmd, "--fields", o->fields, "Fields, comma-separated", any_name());
  cmd->add_option("--config", o->config, "Module config YAML");
  cmd->add_flag("!--no-plots", o->plots, "Skip the matplotlib figures");
  cmd->add_flag("!--no-real-robot", o->real_robot,
                "Skip the real-robot rows (a plant standing in for the real WAM)");
  cmd->add_option("--real-robot-plant", o->real_robot_plant,
                  "The plant standing in for the real WAM (default: data/plants/real-wam.yaml)");
  cmd->add_option("--plant", o->plant, kPlantHelp);
  cmd->add_option("--belief", o->belief,
                  std::string(kBeliefHelp) + "; the real-robot rows start from the survey");
  cmd->add_option("--round-seeds", o->round_seeds,
                  "Seeds of the round of minigolf (default 20, 3 with --quick; 0: skip it)")
      ->check(CLI::Range(0, 1000));
  cmd->callback([o, out, datasets] {
    o->out = *out;
    o->datasets = *datasets;
    if (const char* rev = std::getenv("MINIGOLF_REVISION"))
      o->revision = rev;
    else {
      const std::string cmd = "git -C " + shell_quote(data_dir().parent_path().string()) +
                              " rev-parse --short HEAD 2>/dev/null";
      if (FILE* p = popen(cmd.c_str(), "r")) {
        char buf[64] = "";
        if (std::fgets(buf, sizeof buf, p)) {
          o->revision = buf;
          while (!o->revision.empty() && (o->revision.back() == '\n' || o->revision.back() == '\r'))
            o->revision.pop_back();
        }
        pclose(p);
      }
    }
    experiments::reproduce(*o, [](const std::string& line) {
      fmt::print(stderr, "{}\n", line);
      std::fflush(stderr);
    });
    fmt::print("report: {}\n", (std::filesystem::path(*out) / "report.md").string());
  });
}

}  // namespace

void add_play_commands(CLI::App& app) {
  add_sweep(app);
  add_collect(app);
  add_evaluate(app);
  add_reproduce(app);
}

}  // namespace mg::cli
