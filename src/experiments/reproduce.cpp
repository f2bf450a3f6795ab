// `minigolf reproduce` (reproduce.hpp): checks every input, then runs the steps of
// reproduce_steps.hpp field by field, the parts beyond the thesis (beyond.hpp, real_robot.hpp,
// round_study.hpp), and writes success.csv, run.json and report.md.
#include "experiments/reproduce.hpp"

#include <algorithm>
#include <chrono>
#include <system_error>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "belief/belief.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/plot.hpp"
#include "core/rng.hpp"
#include "experiments/beyond.hpp"
#include "experiments/real_robot.hpp"
#include "experiments/reproduce_steps.hpp"
#include "experiments/round_study.hpp"
#include "system/distributed.hpp"
#include "system/parallel.hpp"

namespace mg::experiments {
namespace {

namespace fs = std::filesystem;
using namespace reproduce_steps;

// Every field loads and (without --collect) has its data sets, before any work starts.
void check_inputs(const ReproduceOptions& opt, const fs::path& datasets) {
  std::error_code ec;
  if (opt.fields.empty()) throw InputError("reproduce: --fields: expected at least one field");
  for (const auto& name : opt.fields) {
    const field::Field fl = field::load_field(name);
    const bool split =
        static_cast<int>(fl.situations.collection_points().size()) >= kSplitMinPoints;
    if (opt.collect) continue;
    for (const fs::path& p : {datasets / (name + ".csv"), datasets / (name + "-validation.csv")}) {
      if (split && p.filename().string().ends_with("-validation.csv")) continue;
      if (!fs::is_regular_file(p, ec))
        throw InputError(
            fmt::format("reproduce: data set {} is missing (run with --collect, or "
                        "scripts/make-datasets.sh)",
                        p.string()));
    }
  }
}

// The parts beyond the thesis of one field: self-teaching, baselines, noise; the real-robot
// rows (a plant stands in for the real WAM on the thesis's real fields).
void beyond_the_thesis(const Run& run, const FieldRun& f,
                       const std::map<std::string, learning::Model>& models, Tables& t) {
  const ReproduceOptions& opt = run.opt;
  const system::System& sys = *f.sys;
  const std::string& name = f.name;
  // ---- beyond the thesis: the robot teaches itself; baselines; noise
  if (opt.beyond) {
    BeyondOptions bo;
    bo.quick = opt.quick;
    bo.threads = opt.threads;
    bo.seed = opt.seed;
    bo.test_situations = run.n_test;
    bo.teacher = f.teacher;
    bo.csv_path = run.csv_path;
    bo.fig_path = run.fig_path;
    bo.plot = run.plot;
    bo.say = run.say;
    for (const auto& [table, rows] : beyond_thesis(sys, name, f.region, models, bo))
      t.beyond_md[table] += rows;
  }
  // ---- the real-robot rows: a plant stands in for the real WAM (the thesis's real fields)
  if (opt.real_robot && (name == "flat" || name == "multiple-hills")) {
    RealRobotOptions ro;
    ro.quick = opt.quick;
    ro.threads = opt.threads;
    ro.seed = opt.seed;
    ro.plant = run.real_plant;
    ro.thesis = [&](const std::string& fl, const std::string& m) {
      return run.thesis.success(fl, m, "real_robot");
    };
    ro.csv_path = run.csv_path;
    ro.fig_path = run.fig_path;
    ro.plot = run.plot;
    ro.say = run.say;
    for (const auto& [table, rows] : real_robot_rows(sys.config(), name, f.region, models, ro))
      t.real_md[table] += rows;
  }
}

// run.json's entry of one field.
nlohmann::json field_json(const FieldRun& f) {
  const system::System& sys = *f.sys;
  return {{"name", f.name},
          {"source", sys.field().source},
          {"region", field::to_string(f.region.shape)},
          {"strategy", f.region.strategy},
          {"learn_speed", f.region.learn_speed},
          {"fixed_speed", f.region.speed},
          {"data_set", f.data_file.string()},
          {"inputs", f.inputs},
          {"outputs", f.outputs},
          {"hitting_model", sys.config().hitting_model},
          {"envelope",
           {sys.config().angle_min, sys.config().angle_max, sys.config().speed_min,
            sys.config().speed_max}}};
}

// The round-of-minigolf section (beyond the thesis), or nothing.
std::string round_of_minigolf(const Run& run) {
  const ReproduceOptions& opt = run.opt;
  std::string rounds_md;
  const int round_seeds = opt.round_seeds >= 0 ? opt.round_seeds : (opt.quick ? 3 : 20);
  if (opt.beyond && round_seeds > 0) {
    RoundStudyOptions ro;
    ro.seeds = round_seeds;
    ro.seed = opt.seed;
    ro.threads = opt.threads;
    ro.config = opt.config;
    ro.plant = opt.plant;
    ro.belief = opt.belief;
    ro.plots = opt.plots;
    rounds_md =
        "\n## Beyond the thesis: a round of minigolf\n\n"
        "Every shipped course, hole after hole from wherever the ball lies (docs/round.md). "
        "**robot**: plans in its own model of each field and hits with the arm (full system), "
        "its launch skill learned from its own putts on each field; **oracle**: plans in the "
        "true world with exact execution, ball-only putts (the best this planner can do); "
        "**greedy**: aims the arm at the hole. Strokes include penalties; a hole ends at "
        "`max_strokes`. Every stroke: `rounds.csv`.\n\n" +
        round_study(ro, opt.out, run.say).markdown;
  }
  return rounds_md;
}

}  // namespace

std::vector<int> arctan_validation_split(int nx, int ny, int n_validation, std::uint64_t seed) {
  std::vector<int> candidates;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const bool corner = (i == 0 || i == nx - 1) && (j == 0 || j == ny - 1);
      if (!corner) candidates.push_back(i * ny + j);
    }
  Rng rng(seed);
  std::shuffle(candidates.begin(), candidates.end(), rng);
  candidates.resize(
      static_cast<std::size_t>(std::min<int>(n_validation, static_cast<int>(candidates.size()))));
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

void reproduce(const ReproduceOptions& opt, const std::function<void(const std::string&)>& log) {
  const auto t_start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  };
  Run run(opt);
  run.thesis = load_thesis();
  run.say = [&](const std::string& s) { log(fmt::format("[{:6.1f} s] {}", elapsed(), s)); };
  run.datasets = opt.datasets.empty() ? data_dir() / "datasets" : opt.datasets;
  // Every input and output is checked before the first step prints or runs.
  check_inputs(opt, run.datasets);
  system::check_threads(opt.threads);
  run.run_plant = opt.plant.empty() ? plant::Plant{} : plant::load_plant(opt.plant);
  if (!opt.belief.empty()) {
    run.run_belief = belief::load_belief(opt.belief).estimate;
    run.run_belief.source = opt.belief;
  }
  run.real_plant = plant::load_plant(opt.real_robot_plant.empty()
                                         ? (data_dir() / "plants" / "real-wam.yaml").string()
                                         : opt.real_robot_plant);
  if (!opt.config.empty())
    for (const auto& name : opt.fields) (void)system::load_config(opt.config, name);
  for (const fs::path& dir : {opt.out, opt.out / "csv", opt.out / "figures"})
    ensure_output_dir(dir);
  for (const char* file : {"report.md", "run.json"}) check_output_file(opt.out / file);
  run.n_test = opt.quick ? 30 : 200;
  run.curve_seeds = opt.quick ? 3 : 10;
  run.curve_situations = 30;
  run.arctan_splits = opt.quick ? 100 : 1000;
  run.plot = [&opt](const std::string& args, const std::string& png) {
    if (!opt.plots || !system::is_root_process()) return;  // one process draws (MPI)
    run_plot_script(args, png);
  };
  run.csv_path = [&opt](const std::string& name) { return (opt.out / "csv" / name).string(); };
  run.fig_path = [&opt](const std::string& name) { return (opt.out / "figures" / name).string(); };

  Tables t;
  nlohmann::json run_json = {{"seed", opt.seed},
                             {"quick", opt.quick},
                             {"revision", opt.revision},
                             {"threads", system::thread_count(opt.threads)},
                             {"fields", nlohmann::json::array()}};
  run_json["belief"] = opt.belief.empty() ? nlohmann::json() : nlohmann::json(opt.belief);
  run_json["plant"] = run.run_plant.source.empty() ? nlohmann::json()
                                                   : nlohmann::json{{"path", run.run_plant.source},
                                                                    {"hash", run.run_plant.hash}};
  for (const std::string& name : opt.fields) {
    const FieldRun f = prepare_field(run, name, t);
    const auto models = validate_models(run, f, t);
    play_test_situations(run, f, models, t);
    learning_curves(run, f, t);
    beyond_the_thesis(run, f, models, t);
    field_figures(run, f, models, t);
    run_json["fields"].push_back(field_json(f));
  }

  const std::string rounds_md = round_of_minigolf(run);
  write_file_atomic(opt.out / "csv" / "success.csv", t.success_csv);
  run.plot(
      fmt::format(
          "success {} {} --title {}", shell_quote(run.csv_path("success.csv")),
          shell_quote(run.fig_path("success.png")),
          shell_quote(
              "success ratio per field and method (95 % Wilson interval; o = oracle ceiling)")),
      run.fig_path("success.png"));
  run_json["elapsed_s"] = elapsed();
  write_file_atomic(opt.out / "run.json", run_json.dump(2) + "\n");
  write_file_atomic(opt.out / "report.md", report_markdown(run, t, rounds_md, elapsed()));
  run.say(fmt::format("report written to {}", (opt.out / "report.md").string()));
}

}  // namespace mg::experiments
