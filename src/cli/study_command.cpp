// study launch-error [--field flat] [--angles-deg -10,0,10] [--hits 10] [--speed 1.0]
//   [--torque-noise 0.01] [--placement-noise 0.001] [--seed 1] [--out DIR] [--json] [--plot]
// The launch-error study of thesis 6.1 (experiments/launch_study.hpp): progress on stderr, a
// Markdown table (or --json) on stdout, DIR/launch_error.{csv,md} and with --plot
// DIR/launch_error.png.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "ds/hitting_model.hpp"
#include "experiments/launch_study.hpp"
#include "field/field.hpp"
#include "system/distributed.hpp"
#include "system/system.hpp"

namespace mg::cli {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

nlohmann::json summary_json(const experiments::LaunchStudyResult& r) {
  const auto& o = r.options;
  nlohmann::json angles = nlohmann::json::array();
  for (const auto& s : r.summary) {
    angles.push_back({{"angle_deg", s.commanded_angle_deg},
                      {"n", s.n},
                      {"missed", s.missed},
                      {"mean_error_deg", number_or_null(s.mean_error_deg)},
                      {"std_error_deg", number_or_null(s.std_error_deg)},
                      {"club_speed_error_mean", number_or_null(s.mean_club_speed_error)},
                      {"club_speed_error_std", number_or_null(s.std_club_speed_error)},
                      {"club_speed_error_pct", number_or_null(s.mean_club_speed_error_pct)},
                      {"launch_club_ratio_mean", number_or_null(s.mean_launch_club_ratio)},
                      {"launch_club_ratio_std", number_or_null(s.std_launch_club_ratio)}});
  }
  return {{"field", r.field},
          {"hole", o.hole},
          {"hits", o.hits},
          {"speed", o.speed},
          {"torque_noise", o.torque_noise},
          {"placement_noise", o.placement_noise},
          {"seed", o.seed},
          {"angles", angles}};
}

}  // namespace

void add_study_commands(CLI::App& app) {
  struct Options {
    std::string field = "flat";
    std::vector<double> angles = experiments::LaunchStudyOptions{}.angles_deg;
    int hits = 10;
    double speed = 1.0;
    double torque_noise = 0.01;
    double placement_noise = 0.001;
    std::uint64_t seed = 1;
    std::string out = "out/study";
    bool json = false;
    bool plot = false;
    std::string config;
    std::string hitting_model;
    int threads = 0;
  };
  auto o = std::make_shared<Options>();
  CLI::App* study =
      app.add_subcommand("study", "Experiments with the simulated arm (thesis ch. 6)");
  study->require_subcommand(1);
  CLI::App* cmd = study->add_subcommand(
      "launch-error",
      "Launch-angle and hitting-speed error of repeated hits with execution noise (thesis 6.1)");
  cmd->add_option("--field", o->field, "Shipped field name or path to a field file")
      ->capture_default_str();
  add_list_option(cmd, "--angles-deg", o->angles, "Commanded hitting angles [deg], comma-separated",
                  finite_number());
  cmd->add_option("--hits", o->hits, "Hits per angle")
      ->check(unsigned_integer(100000))
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--speed", o->speed, "Commanded club speed [m/s]")
      ->check(finite_number(-1e6, 1e6))
      ->capture_default_str();
  cmd->add_option(
         "--torque-noise", o->torque_noise,
         "Joint-torque disturbance std, fraction of each joint's torque limit, per core tick")
      ->check(finite_number(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--placement-noise", o->placement_noise, "Ball placement std per axis [m]")
      ->check(finite_number(0.0, 0.05))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Noise seed")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--out", o->out, "Output directory for launch_error.{csv,md,png}")
      ->capture_default_str();
  cmd->add_option("--config", o->config, "Module config YAML");
  cmd->add_option("--hitting-model", o->hitting_model,
                  "Hitting DS model file (default: the shipped one)");
  cmd->add_option("--threads", o->threads, "Threads (0: all cores; results do not depend on it)")
      ->check(CLI::Range(0, 256));
  cmd->add_flag("--json", o->json, "Print a JSON summary instead of the Markdown table");
  cmd->add_flag("--plot", o->plot, "Also draw DIR/launch_error.png (scripts/plot_launch_error.py)");
  cmd->callback([o] {
    experiments::LaunchStudyOptions opt;
    opt.angles_deg = o->angles;
    opt.hits = o->hits;
    opt.speed = o->speed;
    opt.torque_noise = o->torque_noise;
    opt.placement_noise = o->placement_noise;
    opt.seed = o->seed;
    if (o->out.empty()) throw InputError("--out: expected a directory, got ''");

    const system::System sys(system::load_config(o->config, o->field, o->hitting_model));
    const control::ModuleConfig& config = sys.config();
    for (double a : opt.angles_deg)
      if (a * kDeg < config.angle_min || a * kDeg > config.angle_max)
        throw InputError(
            fmt::format("--angles-deg: expected {:.1f}..{:.1f} deg (safe envelope), got {}",
                        config.angle_min / kDeg, config.angle_max / kDeg, a));
    if (opt.speed < config.speed_min || opt.speed > config.speed_max)
      throw InputError(
          fmt::format("--speed: expected {}..{} m/s (club speed, safe envelope), got {}",
                      config.speed_min, config.speed_max, o->speed));
    opt.validate();
    // The folder and its files, after the inputs, before the hits.
    ensure_output_dir(o->out);
    for (const char* file : {"launch_error.csv", "launch_error.md", "launch_error.png"})
      if (o->plot || std::string_view(file) != "launch_error.png")
        check_output_file(std::filesystem::path(o->out) / file);

    opt.hole = sys.field().hole.position;

    const int total = static_cast<int>(opt.angles_deg.size()) * opt.hits;
    int done = 0;
    const experiments::LaunchStudyResult r =
        experiments::run_launch_study(sys, opt, o->threads, [&](const experiments::LaunchHit& h) {
          ++done;
          if (h.hit)
            fmt::print(stderr,
                       "[{}/{}] angle {:g} deg hit {}: launch error {:+.3f} deg, club {:.3f} m/s, "
                       "launch {:.3f} m/s\n",
                       done, total, h.commanded_angle_deg, h.hit_index, h.launch_error_deg,
                       h.club_speed, h.launch_speed);
          else
            fmt::print(stderr, "[{}/{}] angle {:g} deg hit {}: missed ({}; rest time {:.2f} s)\n",
                       done, total, h.commanded_angle_deg, h.hit_index, h.failure, h.rest_time);
          std::fflush(stderr);
        });

    const std::filesystem::path dir(o->out);
    const std::string markdown = experiments::launch_study_markdown(r);
    write_file_atomic(dir / "launch_error.csv", experiments::launch_study_csv(r));
    write_file_atomic(dir / "launch_error.md", markdown);
    if (o->plot && system::is_root_process()) {  // one process draws (MPI)
      const std::filesystem::path script =
          data_dir().parent_path() / "scripts" / "plot_launch_error.py";
      const std::string command = "/usr/bin/python3 " + shell_quote(script.string()) + " " +
                                  shell_quote((dir / "launch_error.csv").string()) + " " +
                                  shell_quote((dir / "launch_error.png").string()) + " 1>&2";
      if (std::system(command.c_str()) != 0)
        throw Error(fmt::format("--plot: {} failed", script.string()));
    }
    if (o->json)
      fmt::print("{}\n", summary_json(r).dump());
    else
      fmt::print("{}", markdown);
  });
}

}  // namespace mg::cli
