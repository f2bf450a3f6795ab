// putt --field F --hole X,Y --angle RAD --speed M/S [--ball X,Y [--aim RAD]] [--ball-only]
//      [--hitting-model FILE] [--config FILE] [--plant FILE] [--json] [--trajectory FILE]
// Without --ball-only the simulated WAM hits the ball (control/full_system.hpp); --angle and
// --speed are then the hitting angle (in the frame of the base, which stands beside the ball
// facing --aim: system::stance_for) and the club speed at the ball.
#include <cmath>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "sim/putt.hpp"
#include "system/system.hpp"
#include "viz/figure_data.hpp"

namespace mg::cli {
namespace {

// The keys shared by the ball-only and the full-system putt.
nlohmann::json outcome_json(const std::string& field, std::array<double, 2> hole, double angle,
                            double speed, const sim::PuttOutcome& out) {
  return {
      {"field", field},
      {"hole", hole},
      {"angle", angle},
      {"speed", speed},
      {"sunk", out.sunk},
      {"end", sim::to_string(out.end)},
      {"rest_position", out.rest_position},
      {"closest_approach", out.closest_approach},
      {"duration", out.duration},
      {"steps", out.steps},
  };
}

// Trajectory samples are 10 ms apart (the recorded outcome is the same bits as without).
constexpr double kTrajectoryInterval = 0.01;

// The arm hits the ball: the module runs in lockstep simulator mode.
void run_full_system_putt(const std::string& field_name, const std::string& hole_text,
                          const std::string& ball_text, std::optional<double> aim, double angle,
                          double speed, double max_duration, const std::string& model_path,
                          const std::string& config_path, const std::string& plant_path, bool json,
                          const std::string& trajectory_path) {
  const system::System sys(system::load_config(config_path, field_name, model_path),
                           load_plant_arg(plant_path));
  sys.check_request(angle, speed, "putt");
  const auto hole =
      hole_text.empty() ? sys.field().hole.position : parse_vector<2>("--hole", hole_text);
  system::SystemData data(sys);
  control::FullPuttOptions options;
  options.max_duration = max_duration;
  options.record_interval = trajectory_path.empty() ? 0.0 : kTrajectoryInterval;
  const auto ball = ball_text.empty() ? sys.field().tee : parse_vector<2>("--ball", ball_text);
  if (!ball_text.empty() || aim) {
    system::check_ball_position(sys.field(), ball, "--ball");
    options.stance = system::putt_stance(sys, ball, hole, aim);
  }
  const control::FullPuttResult r = system::arm_putt(sys, data, hole, angle, speed, options);
  const sim::World& world = sys.arm_world();
  if (r.hit_refused) throw InputError("putt: the module refused the hit request");
  if (!r.hit) throw NumericalError("putt: the club did not reach the ball");
  const sim::PuttOutcome& out = r.outcome;
  if (!trajectory_path.empty()) write_file_atomic(trajectory_path, viz::trajectory_csv(out));
  if (json) {
    nlohmann::json j = outcome_json(world.field().name, hole, angle, speed, out);
    j["plant"] = plant_json(sys.plant());
    j["ball"] = r.ball_start;
    j["aim"] = options.stance.yaw;
    j["club"] = {{"angle", r.club.angle}, {"speed", r.club.speed}};
    j["launch"] = {{"angle", r.launch.angle}, {"speed", r.launch.speed}};
    j["timing"] = {{"core_update_p99_us", r.timing.core_update_p99_us},
                   {"core_update_max_us", r.timing.core_update_max_us},
                   {"overruns", r.timing.overruns}};
    fmt::print("{}\n", j.dump());
  } else {
    fmt::print(
        "{} on {} (arm): angle {:.4f} rad, club {:.3f} m/s -> launch {:.4f} rad, {:.3f} m/s; "
        "{} after {:.2f} s; rest ({:.3f}, {:.3f}) m; closest approach {:.4f} m; core update "
        "p99 {:.1f} us\n",
        out.sunk ? "SUNK" : "missed", world.field().name, angle, r.club.speed, r.launch.angle,
        r.launch.speed, sim::to_string(out.end), out.duration, out.rest_position[0],
        out.rest_position[1], out.closest_approach, r.timing.core_update_p99_us);
  }
}

}  // namespace

void add_putt_command(CLI::App& app) {
  struct Options {
    std::string field = "flat";
    std::string hole;
    std::string ball;
    std::optional<double> aim;
    double angle = 0.0;
    double speed = 0.0;
    double max_duration = 30.0;
    bool ball_only = false;
    bool json = false;
    std::string trajectory;
    std::string hitting_model;
    std::string config;
    std::string plant;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("putt", "Simulate one putt and report the outcome");
  cmd->add_option("--field", o->field, "Shipped field name or path to a field file")
      ->capture_default_str();
  cmd->add_option("--hole", o->hole, "Hole centre X,Y in metres (default: the field's)");
  cmd->add_option("--ball", o->ball, "Where the ball lies X,Y in metres (default: the tee)");
  cmd->add_option("--aim", o->aim,
                  "With the arm: the direction [rad, world] the base's hitting frame faces "
                  "(default: from --ball to the hole; without --ball 0)");
  cmd->add_option("--angle", o->angle,
                  "Launch angle [rad], counter-clockwise from +x (with the arm: the hitting "
                  "angle in the base's frame)")
      ->required();
  cmd->add_option("--speed", o->speed, "Launch speed [m/s] (with the arm: club speed)")->required();
  cmd->add_option("--max-duration", o->max_duration, "Give up after this simulated time [s]")
      ->capture_default_str();
  cmd->add_flag("--ball-only", o->ball_only, "Launch the ball directly (no arm)");
  cmd->add_flag("--json", o->json, "Print one JSON object");
  cmd->add_option("--trajectory", o->trajectory,
                  "Write the ball trajectory to this CSV file (t from the launch; with the arm, "
                  "from the club's first contact)");
  cmd->add_option("--hitting-model", o->hitting_model,
                  "Hitting DS model file (default: data/models/hitting-default.json)");
  cmd->add_option("--config", o->config,
                  "Module config YAML (gains, envelope, ...; see notes/control.md)");
  cmd->add_option("--plant", o->plant, kPlantHelp);
  cmd->callback([o] {
    if (!o->ball_only) {
      run_full_system_putt(o->field, o->hole, o->ball, o->aim, o->angle, o->speed, o->max_duration,
                           o->hitting_model, o->config, o->plant, o->json, o->trajectory);
      return;
    }
    sim::PuttRequest request;
    request.angle = o->angle;
    request.speed = o->speed;
    request.max_duration = o->max_duration;
    request.record_interval = o->trajectory.empty() ? 0.0 : kTrajectoryInterval;
    request.validate();
    if (o->aim)
      throw InputError("--aim: only with the arm (a ball-only putt's --angle is its aim)");
    const system::System sys(system::load_config(o->config, o->field, o->hitting_model),
                             load_plant_arg(o->plant));
    if (!o->ball.empty()) {
      request.start = parse_vector<2>("--ball", o->ball);
      system::check_ball_position(sys.field(), *request.start, "--ball");
    }
    const sim::World& world = sys.ball_world();
    const auto hole =
        o->hole.empty() ? sys.field().hole.position : parse_vector<2>("--hole", o->hole);
    field::check_hole_position(sys.field(), hole);
    const auto real = system::real_hole(sys, hole);
    field::check_hole_position(world.field(), real);
    system::SystemData data(sys);
    const sim::PuttOutcome out = simulate_putt(world, data.ball.get(), real, request);

    if (!o->trajectory.empty()) write_file_atomic(o->trajectory, viz::trajectory_csv(out));
    if (o->json) {
      nlohmann::json j = outcome_json(world.field().name, hole, o->angle, o->speed, out);
      j["plant"] = plant_json(sys.plant());
      j["ball"] = request.start ? *request.start : sys.field().tee;
      fmt::print("{}\n", j.dump());
    } else {
      fmt::print(
          "{} on {}: angle {:.4f} rad, speed {:.3f} m/s -> {} after {:.2f} s; rest ({:.3f}, "
          "{:.3f}) m; closest approach {:.4f} m\n",
          out.sunk ? "SUNK" : "missed", world.field().name, o->angle, o->speed,
          sim::to_string(out.end), out.duration, out.rest_position[0], out.rest_position[1],
          out.closest_approach);
    }
  });
}

}  // namespace mg::cli
