// ds demos | ds fit | ds check | ds rollout (the hitting motion; see notes/ds.md).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/json_io.hpp"
#include "ds/demonstrations.hpp"
#include "ds/hitting_ds.hpp"
#include "ds/hitting_model.hpp"
#include "ds/seds.hpp"
#include "stats/gmm_io.hpp"

namespace mg::cli {
namespace {

std::filesystem::path resolve_model(const std::string& name) {
  // "default" is the shipped model; anything else is a path.
  if (name == "default") return data_dir() / "models" / "hitting-default.json";
  return name;
}

Eigen::Vector3d parse_point(const std::string& what, const std::string& text) {
  const auto v = parse_vector<3>(what, text);
  return {v[0], v[1], v[2]};
}

nlohmann::json vec_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
}

void add_demos(CLI::App& ds) {
  struct Opts {
    std::string out;
    std::uint64_t seed = 1;
    int count = 8;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd =
      ds.add_subcommand("demos", "Generate synthetic human-like hitting demonstrations (CSV)");
  cmd->add_option("-o,--output", o->out, "Output CSV: demo,t,x,y,z,vx,vy,vz (m, s, world frame)")
      ->check(output_file())
      ->required();
  cmd->add_option("--seed", o->seed, "Random seed")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--count", o->count, "Number of demonstrations")->capture_default_str();
  cmd->callback([o] {
    ds::DemoGeneratorConfig cfg;
    cfg.count = o->count;
    Rng rng(o->seed);
    const auto demos = ds::generate_demonstrations(cfg, rng);
    write_file_atomic(o->out,
                      "# minigolf hitting demonstrations: metres, seconds, world frame (ball at "
                      "0,0,0.02135; +x = psi0)\n" +
                          ds::format_demonstrations(demos));
    std::size_t n = 0;
    for (const auto& d : demos) n += d.size();
    fmt::print("wrote {} demonstrations ({} samples) to {}\n", demos.size(), n, o->out);
  });
}

void add_fit(CLI::App& ds) {
  struct Opts {
    std::string demos, out, objective = "likelihood";
    int gaussians = 4;
    std::uint64_t seed = 1;
    int max_evaluations = 1500;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd =
      ds.add_subcommand("fit", "Fit a hitting model (SEDS + strength GMM) to demonstrations");
  cmd->add_option("demos", o->demos, "Demonstrations CSV")->required();
  cmd->add_option("-o,--output", o->out, "Output hitting model (JSON)")
      ->check(output_file())
      ->required();
  cmd->add_option("--gaussians", o->gaussians, "Number of Gaussians K")
      ->check(CLI::Range(1, ds::kMaxSedsGaussians))
      ->capture_default_str();
  cmd->add_option("--objective", o->objective, "likelihood | mse")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of k-means++/EM")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--max-evaluations", o->max_evaluations, "NLopt objective evaluations at most")
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print one JSON object");
  cmd->callback([o] {
    const auto demos = ds::read_demonstrations(o->demos);
    ds::HittingFitOptions opt;
    opt.seds.gaussians = o->gaussians;
    opt.seds.objective = ds::parse_seds_objective(o->objective);
    opt.seds.seed = o->seed;
    opt.seds.max_evaluations = o->max_evaluations;
    // On a terminal, the fit's evaluations (up to --max-evaluations per attempt; a fit that
    // needs a fallback makes more attempts, each noted afterwards).
    std::optional<Progress> progress;
    if (!o->json && isatty(fileno(stderr)) != 0) {
      progress.emplace(fmt::format("SEDS fit, K = {}", o->gaussians), o->max_evaluations);
      opt.seds.on_evaluation = [&progress](int evaluations) {
        if (evaluations % 10 == 0) progress->update(evaluations);
      };
    }
    ds::HittingFitReport rep;
    ds::HittingModel model = ds::fit_hitting_model(demos, opt, &rep);
    if (progress) progress->finish();
    const auto err = ds::reproduction_error(model, demos);
    model.provenance["demonstrations_file"] = std::filesystem::path(o->demos).filename().string();
    model.provenance["reproduction"] = {{"velocity_rmse", err.velocity_rmse},
                                        {"direction_rmse", err.direction_rmse},
                                        {"seds_direction_rmse", err.seds_direction_rmse},
                                        {"speed_rmse", err.speed_rmse},
                                        {"mean_path_distance", err.mean_path_distance},
                                        {"max_path_distance", err.max_path_distance}};
    ds::write_hitting_model(o->out, model);
    nlohmann::json j{{"output", o->out},
                     {"max_eigenvalue", model.max_eigenvalue()},
                     {"default_speed", model.default_speed()},
                     {"fit_seconds", rep.fit_seconds},
                     {"evaluations", rep.seds.evaluations},
                     {"initial_objective", rep.seds.initial_objective},
                     {"final_objective", rep.seds.final_objective},
                     {"samples", rep.samples_used},
                     {"velocity_rmse", err.velocity_rmse},
                     {"direction_rmse", err.direction_rmse},
                     {"seds_direction_rmse", err.seds_direction_rmse},
                     {"speed_rmse", err.speed_rmse},
                     {"mean_path_distance", err.mean_path_distance},
                     {"max_path_distance", err.max_path_distance},
                     {"demos_reached", err.all_reached},
                     {"demos", demos.size()},
                     {"gaussians", rep.seds.components.size()},
                     {"notes", rep.notes}};
    if (o->json) {
      fmt::print("{}\n", j.dump());
      return;
    }
    for (const auto& note : rep.notes) fmt::print(stderr, "minigolf: note: {}\n", note);
    fmt::print("wrote {}\n", o->out);
    fmt::print("  SEDS          K = {}, objective {}, {} samples, {} evaluations, {:.2f} s\n",
               rep.seds.components.size(), o->objective, rep.samples_used, rep.seds.evaluations,
               rep.fit_seconds);
    fmt::print("  objective     {:.6g} -> {:.6g}\n", rep.seds.initial_objective,
               rep.seds.final_objective);
    fmt::print("  stability     max eigenvalue of A_k + A_k^T = {:.6g} 1/s\n",
               model.max_eigenvalue());
    fmt::print("  v(x*)         {:.4f} m/s\n", model.default_speed());
    fmt::print(
        "  reproduction  velocity RMSE {:.4f} m/s (speed {:.4f} m/s), direction RMSE {:.2f} deg "
        "(bare SEDS {:.2f} deg)\n",
        err.velocity_rmse, err.speed_rmse, err.direction_rmse * 180.0 / std::numbers::pi,
        err.seds_direction_rmse * 180.0 / std::numbers::pi);
    fmt::print(
        "                rollouts from the demo starts: path distance mean {:.4f} m, max {:.4f} m, "
        "{}/{} reach the ball\n",
        err.mean_path_distance, err.max_path_distance, err.all_reached, demos.size());
  });
}

void add_check(CLI::App& ds) {
  struct Opts {
    std::string model;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd =
      ds.add_subcommand("check", "Verify the SEDS stability constraints of a hitting model");
  cmd->add_option("model", o->model, "Hitting model JSON (or 'default')")->required();
  cmd->add_flag("--json", o->json, "Print one JSON object");
  cmd->callback([o] {
    const auto path = resolve_model(o->model);
    const nlohmann::json j = read_json_file(path);
    // The constraints first (so a violating file is still reported), then the full validation.
    stats::Gmm gmm;
    try {
      gmm = stats::gmm_from_json(j.at("seds").at("gmm"), path.string() + ": seds.gmm");
    } catch (const nlohmann::json::exception& e) {
      throw InputError(fmt::format("{}: malformed hitting model: {}", path.string(), e.what()));
    }
    double bias = 0.0;
    const double max_eig = ds::seds_check(gmm, &bias);
    const bool stable = max_eig <= -1e-4 && bias <= 1e-6;
    std::string problem;
    if (stable) {
      try {
        ds::hitting_model_from_json(j, path.string());
      } catch (const InputError& e) {
        problem = e.what();
      }
    }
    const bool ok = stable && problem.empty();
    if (o->json) {
      fmt::print("{}\n", nlohmann::json{{"ok", ok},
                                        {"stable", stable},
                                        {"max_eigenvalue", max_eig},
                                        {"max_bias", bias},
                                        {"components", gmm.num_components()},
                                        {"problem", problem}}
                             .dump());
    } else {
      fmt::print(
          "{}: {} components, max eigenvalue of A_k + A_k^T = {:.6g} 1/s (required <= -1e-4), "
          "max |b_k + A_k x*| (relative) = {:.3g}: {}\n",
          path.string(), gmm.num_components(), max_eig, bias, ok ? "OK" : "FAILED");
    }
    if (!stable)
      throw NumericalError(
          fmt::format("{}: SEDS stability constraints violated (max eigenvalue {}, bias {})",
                      path.string(), max_eig, bias));
    if (!problem.empty()) throw InputError(problem);
  });
}

void add_rollout(CLI::App& ds) {
  struct Opts {
    std::string model, start = "-0.35,0.05,0.15", modulator = "constant", out;
    double angle = 0.0;
    double speed = -1.0;
    double dt = 0.002;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* cmd = ds.add_subcommand(
      "rollout", "Integrate the hitting DS from a start point until the ball is reached");
  cmd->add_option("model", o->model, "Hitting model JSON (or 'default')")->required();
  cmd->add_option("--start", o->start, "Start position X,Y,Z [m, world]")->capture_default_str();
  cmd->add_option("--angle", o->angle, "Hitting angle theta [rad] about +z from psi0")
      ->capture_default_str();
  CLI::Option* speed_opt = cmd->add_option(
      "--speed", o->speed, "Hitting speed at the ball [m/s] (default: the model's v(x*))");
  cmd->add_option("--modulator", o->modulator, "constant | sine")->capture_default_str();
  cmd->add_option("--dt", o->dt, "Integration step [s] (RK4)")->capture_default_str();
  cmd->add_option("-o,--output", o->out, "Trajectory CSV: t,x,y,z,vx,vy,vz")->check(output_file());
  cmd->add_flag("--json", o->json, "Print one JSON object");
  cmd->callback([o, speed_opt] {
    const ds::HittingModel model = ds::read_hitting_model(resolve_model(o->model));
    ds::HittingCommand c;
    c.start = parse_point("--start", o->start);
    c.angle = o->angle;
    c.speed = speed_opt->count() > 0 ? o->speed : model.default_speed();
    c.modulator = ds::parse_modulator(o->modulator);
    ds::RolloutOptions ro;
    ro.dt = o->dt;
    ro.record = !o->out.empty();
    const ds::RolloutResult r = ds::rollout(model, c, ro);
    if (!o->out.empty()) write_file_atomic(o->out, ds::format_rollout(r));
    const Eigen::Vector3d want = ds::rotation_about_z(c.angle) * model.psi0();
    const double angle_error = angle_between(r.velocity, want);
    const double speed_error = r.velocity.norm() - c.speed;
    if (o->json) {
      fmt::print("{}\n", nlohmann::json{{"reached", r.reached},
                                        {"stop_reason", r.stop_reason},
                                        {"position_error", r.position_error},
                                        {"velocity", vec_json(r.velocity)},
                                        {"speed", r.velocity.norm()},
                                        {"duration", r.duration},
                                        {"hit_position", vec_json(r.hit_position)},
                                        {"angle_error", angle_error},
                                        {"speed_error", speed_error},
                                        {"steps", r.steps}}
                             .dump());
    } else {
      fmt::print("{}: {} after {:.3f} s ({} steps)\n",
                 r.reached ? "reached the ball" : "did NOT reach the ball", r.stop_reason,
                 r.duration, r.steps);
      fmt::print("  position error  {:.3e} m\n", r.position_error);
      fmt::print(
          "  velocity        ({:.4f}, {:.4f}, {:.4f}) m/s, speed {:.4f} m/s (requested {:.4f})\n",
          r.velocity.x(), r.velocity.y(), r.velocity.z(), r.velocity.norm(), c.speed);
      fmt::print("  direction error {:.4f} deg from R(theta) psi0\n",
                 angle_error * 180.0 / std::numbers::pi);
    }
    if (!r.reached) throw NumericalError(fmt::format("ball not reached ({})", r.stop_reason));
  });
}

}  // namespace

void add_ds_commands(CLI::App& app) {
  CLI::App* ds =
      app.add_subcommand("ds", "The hitting motion: demonstrations, SEDS fit, checks, rollouts");
  ds->require_subcommand(1);
  add_demos(*ds);
  add_fit(*ds);
  add_check(*ds);
  add_rollout(*ds);
}

}  // namespace mg::cli
