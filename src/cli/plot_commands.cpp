// plot ds | strength | field | model: figures of the models (thesis figs 2.2-2.4, 5.4b, 6.3-6.9);
// plot round: a round of minigolf played, one figure per hole.
//
// Each exports the numbers it needs as CSV (a temporary folder, or --data-dir to keep them) and
// draws them with scripts/plots/plot.py (/usr/bin/python3, matplotlib): one PNG (plot round: one
// per hole). A missing or malformed input: one line, exit 2.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "ds/demonstrations.hpp"
#include "ds/hitting_model.hpp"
#include "game/round.hpp"
#include "system/system.hpp"
#include "viz/figure_data.hpp"
#include "viz/round_figure.hpp"

namespace mg::cli {

namespace {

namespace fs = std::filesystem;

struct DsArgs {
  std::string hitting_model, demos, plane = "xz", out, data_dir;
  std::vector<double> speeds{0.5, 1.0, 1.5};  ///< strength: club speeds of the modulator curves
};

void add_ds_inputs(CLI::App* cmd, DsArgs& a) {
  cmd->add_option("--hitting-model", a.hitting_model,
                  "Hitting DS model (default: the shipped one)");
  cmd->add_option("--demos", a.demos, "Demonstrations CSV (default: data/demos/default.csv)");
  cmd->add_option("-o,--output", a.out, "PNG to write")->check(output_file())->required();
  cmd->add_option("--data-dir", a.data_dir, "Keep the exported CSV files here");
}

struct DsInputs {
  ds::HittingModel model;
  std::vector<ds::Demonstration> demos;
};

DsInputs load_ds_inputs(const DsArgs& a) {
  const control::ModuleConfig config = system::load_config("", "", a.hitting_model);
  DsInputs in{ds::read_hitting_model(config.hitting_model),
              ds::read_demonstrations(
                  system::resolve_data_path(a.demos.empty() ? "data/demos/default.csv" : a.demos))};
  if (in.demos.empty()) throw InputError("plot: no demonstrations");
  return in;
}

void add_plot_ds(CLI::App* plot) {
  auto a = std::make_shared<DsArgs>();
  CLI::App* cmd = plot->add_subcommand(
      "ds", "The hitting DS: demonstrations, GMM ellipses (2 sigma), streamlines");
  add_ds_inputs(cmd, *a);
  cmd->add_option("--plane", a->plane, "xz (side view through x*) | xy (top view)")
      ->capture_default_str();
  cmd->callback([a] {
    const viz::DsPlane plane = viz::parse_ds_plane(a->plane);
    const DsInputs in = load_ds_inputs(*a);
    const PlotDataDir dir(a->data_dir);
    const auto demos =
        dir.write("ds_demonstrations.csv", viz::demonstrations_csv(in.demos, in.model));
    const auto gmm = dir.write("ds_gmm.csv", viz::gmm_csv(in.model));
    const auto field = dir.write("ds_field.csv", viz::ds_field_csv(in.model, in.demos, plane));
    const auto& xs = in.model.x_star();
    run_plot_script(
        fmt::format("ds {} {} {} {} --plane {} --target={},{},{}", shell_quote(demos.string()),
                    shell_quote(gmm.string()), shell_quote(field.string()), shell_quote(a->out),
                    a->plane, xs.x(), xs.y(), xs.z()),
        a->out);
    fmt::print("wrote {} ({} demonstrations, {} Gaussians, {} plane)\n", a->out, in.demos.size(),
               in.model.seds_gmm().num_components(), a->plane);
  });
}

void add_plot_strength(CLI::App* plot) {
  auto a = std::make_shared<DsArgs>();
  CLI::App* cmd = plot->add_subcommand(
      "strength", "The strength factor along the demonstrations and both speed modulators");
  add_ds_inputs(cmd, *a);
  add_list_option(cmd, "--speeds", a->speeds,
                  "Club speeds v^d [m/s] of the modulator curves, comma-separated",
                  finite_number());
  cmd->callback([a] {
    const std::vector<double>& speeds = a->speeds;
    const DsInputs in = load_ds_inputs(*a);
    const PlotDataDir dir(a->data_dir);
    const auto strength = dir.write("strength.csv", viz::strength_csv(in.model, in.demos));
    const auto mods = dir.write("modulators.csv", viz::modulators_csv(in.model, in.demos, speeds));
    run_plot_script(
        fmt::format("strength {} {} {} --default-speed {}", shell_quote(strength.string()),
                    shell_quote(mods.string()), shell_quote(a->out), in.model.default_speed()),
        a->out);
    fmt::print("wrote {} (v(x*) = {:.3f} m/s, {} demonstrations)\n", a->out,
               in.model.default_speed(), in.demos.size());
  });
}

void add_plot_field(CLI::App* plot) {
  struct Args {
    std::string config, field = "flat", hole, out, data_dir;
    std::vector<std::string> shots;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd =
      plot->add_subcommand("field", "A field's height colour map with ball-only trajectories");
  cmd->add_option("--field", a->field, "Shipped field name or path")->capture_default_str();
  cmd->add_option("--config", a->config, "Module config YAML");
  cmd->add_option("--hole", a->hole, "Hole centre X,Y [m] (default: the field's)");
  cmd->add_option(
      "--shot", a->shots,
      "ANGLE,SPEED launch of a ball-only putt [rad, m/s]; repeat (default: 3 at the hole)");
  cmd->add_option("-o,--output", a->out, "PNG to write")->check(output_file())->required();
  cmd->add_option("--data-dir", a->data_dir, "Keep the exported CSV files here");
  cmd->callback([a] {
    const system::System sys(system::load_config(a->config, a->field));
    const field::Field& f = sys.field();
    const std::array<double, 2> hole =
        a->hole.empty() ? f.hole.position : parse_vector<2>("--hole", a->hole);
    field::check_hole_position(f, hole);
    std::vector<std::array<double, 2>> shots;
    for (const auto& s : a->shots) shots.push_back(parse_vector<2>("--shot", s));
    if (shots.empty()) {
      const double dir = std::atan2(hole[1] - f.tee[1], hole[0] - f.tee[0]);
      for (double v : {0.9, 1.2, 1.5}) shots.push_back({dir, v});
    }
    for (const auto& s : shots)
      if (!(s[1] > 0.0 && s[1] <= 10.0))
        throw InputError(fmt::format("--shot: speed {} m/s: expected (0, 10]", s[1]));
    const PlotDataDir dir(a->data_dir);
    const auto heights = dir.write("field_heights.csv", viz::heights_csv(f));
    system::SystemData d(sys);
    std::string args;
    for (std::size_t k = 0; k < shots.size(); ++k) {
      const auto out = system::ball_putt(sys, d, hole, shots[k][0], shots[k][1], 0.01);
      const auto t = dir.write(fmt::format("field_path_{}.csv", k), viz::trajectory_csv(out));
      args += fmt::format(" --trajectory {}", shell_quote(t.string()));
    }
    if (!f.obstacles.empty())
      args += " --obstacles " +
              shell_quote(dir.write("field_obstacles.csv", viz::obstacles_csv(f)).string());
    run_plot_script(
        fmt::format("field {} {}{} --hole={},{} --hole-diameter {} --tee={},{} --title {}",
                    shell_quote(heights.string()), shell_quote(a->out), args, hole[0], hole[1],
                    f.hole.diameter, f.tee[0], f.tee[1],
                    shell_quote(fmt::format("{}: height map and ball-only paths", f.name))),
        a->out);
    fmt::print("wrote {} ({} ball paths, {} obstacles)\n", a->out, shots.size(),
               f.obstacles.size());
  });
}

void add_plot_model(CLI::App* plot) {
  struct Args {
    std::string model, data, validation, output, out, data_dir;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = plot->add_subcommand(
      "model", "A learner's prediction surface with +-2 sigma and its training points");
  cmd->add_option("--model", a->model, "Parameter model JSON (minigolf train)")->required();
  cmd->add_option("--data", a->data, "Its training data CSV")->required();
  cmd->add_option("--validation", a->validation, "Validation data CSV (drawn as well)");
  cmd->add_option("--output", a->output, "Which output (default: the model's first)");
  cmd->add_option("-o,--out", a->out, "PNG to write")->check(output_file())->required();
  cmd->add_option("--data-dir", a->data_dir, "Keep the exported CSV files here");
  cmd->callback([a] {
    const learning::Model model = learning::load_model(system::resolve_data_path(a->model));
    const learning::Dataset data = learning::load_dataset(system::resolve_data_path(a->data),
                                                          model.input_names, model.output_names);
    if (!a->validation.empty())
      learning::load_dataset(system::resolve_data_path(a->validation), model.input_names,
                             model.output_names);
    const std::string output = a->output.empty() ? model.output_names.front() : a->output;
    if (std::find(model.output_names.begin(), model.output_names.end(), output) ==
        model.output_names.end())
      throw InputError(fmt::format("--output '{}': the model's outputs are {}", output,
                                   fmt::join(model.output_names, ", ")));
    const PlotDataDir dir(a->data_dir);
    const auto pred = dir.write("model_predictions.csv", viz::predictions_csv(model, data));
    std::string inputs;
    for (const auto& n : model.input_names) inputs += (inputs.empty() ? "" : ",") + n;
    run_plot_script(
        fmt::format(
            "model {} --predictions {} --train {}{} --output {} --inputs {} --title {}",
            shell_quote(a->out), shell_quote(pred.string()),
            shell_quote(system::resolve_data_path(a->data).string()),
            a->validation.empty()
                ? ""
                : " --validation " + shell_quote(system::resolve_data_path(a->validation).string()),
            shell_quote(output), shell_quote(inputs),
            shell_quote(fmt::format("{} {}: mean ± 2σ and training points",
                                    learning::method_name(model.method), output))),
        a->out);
    fmt::print("wrote {} ({} training points, output {})\n", a->out, data.inputs.rows(), output);
  });
}

void add_plot_round(CLI::App* plot) {
  struct Args {
    std::string course, player = "robot", out, stem, data_dir;
    std::uint64_t seed = 0;
    int seeds = 1, budget = 6;
    SystemArgs system;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = plot->add_subcommand(
      "round", "A round of minigolf played: every hole's ball paths over its field, one PNG each");
  cmd->add_option("--course", a->course, "Shipped course name or path to a course file")
      ->required();
  cmd->add_option("--player", a->player, "robot (the arm, its own model), oracle or greedy")
      ->check(CLI::IsMember({"robot", "oracle", "greedy"}))
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Seed of the first round")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--seeds", a->seeds, "Rounds, seeds from --seed on, drawn together")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--budget", a->budget, "The robot's learning putts per field (1..50)")
      ->check(CLI::Range(1, 50))
      ->capture_default_str();
  cmd->add_option("--stem", a->stem, "File names STEM-hole<K>.png (default: the course's name)");
  cmd->add_option("-o,--output", a->out, "Folder for the PNGs (made when missing)")->required();
  cmd->add_option("--data-dir", a->data_dir, "Keep the exported CSV files here");
  cmd->add_option("--config", a->system.config, "Module config YAML");
  cmd->add_option("--hitting-model", a->system.hitting_model,
                  "Hitting DS model file (default: the shipped one)");
  cmd->add_option("--plant", a->system.plant, kPlantHelp);
  cmd->add_option("--threads", a->system.threads,
                  "Threads (0: all cores; results do not depend on it)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd->callback([a] {
    const game::Course course = game::load_course(a->course);
    game::RoundOptions o;
    o.player = game::parse_player(a->player, "--player");
    o.calibration_putts = a->budget;
    o.planner.threads = a->system.threads;
    o.validate();
    const std::string stem = a->stem.empty() ? course.name : a->stem;
    if (stem.find('/') != std::string::npos)
      throw InputError(fmt::format("--stem '{}': expected a file name without '/'", stem));
    ensure_output_dir(a->out);  // before the rounds: a bad folder fails fast
    const auto config = system::load_config(a->system.config, "", a->system.hitting_model);
    const plant::Plant plant = load_plant_arg(a->system.plant);
    game::ImaginedCache cache;  // shared by the seeds: the same imagined putts are not repeated
    std::vector<game::RoundResult> rounds;
    Progress progress(fmt::format("plot round {} ({})", course.name, a->player), a->seeds);
    for (int s = 0; s < a->seeds; ++s) {
      o.seed = a->seed + static_cast<std::uint64_t>(s);
      rounds.push_back(game::play_round(course, config, plant, o, &cache));
      progress.update(s + 1);
    }
    progress.finish();
    const auto pngs = viz::plot_round_holes(course, rounds, a->out, stem, a->data_dir);
    for (std::size_t h = 0; h < pngs.size(); ++h)
      fmt::print("wrote {} (hole {}: {}, par {}, {:.2f} strokes over {} round{})\n",
                 pngs[h].string(), h + 1, course.holes[h].field.name, course.holes[h].par,
                 viz::mean_hole_strokes(rounds, h), rounds.size(), rounds.size() == 1 ? "" : "s");
  });
}

}  // namespace

void add_plot_commands(CLI::App& app) {
  CLI::App* plot = app.add_subcommand(
      "plot", "Figures of the models and rounds: ds | strength | field | model | round");
  plot->require_subcommand(1);
  add_plot_ds(plot);
  add_plot_strength(plot);
  add_plot_field(plot);
  add_plot_model(plot);
  add_plot_round(plot);
}

}  // namespace mg::cli
