// putt --field F --hole X,Y --angle RAD --speed M/S [--ball X,Y [--aim RAD]] [--ball-only]
//      [--hitting-model FILE] [--config FILE] [--plant FILE] [--json] [--trajectory FILE]
// Without --ball-only the simulated WAM hits the ball (sim_backend/full_system.hpp); --angle and
// --speed are then the hitting angle (in the frame of the base, which stands beside the ball
// facing --aim: system::stance_for) and the club speed at the ball. The putt and its JSON are
// system::putt's and system::putt_json's, as Python's System.putt.
#include <cmath>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/perception_args.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "sim/putt.hpp"
#include "system/putt.hpp"
#include "system/system.hpp"
#include "vision/camera_perception.hpp"
#include "viz/figure_data.hpp"

namespace mg::cli {
namespace {

void print_text(const system::System& sys, const system::PuttSpec& spec,
                const system::PuttReport& r) {
  const sim::PuttOutcome& out = r.outcome;
  if (spec.ball_only) {
    fmt::print(
        "{} on {}: angle {:.4f} rad, speed {:.3f} m/s -> {} after {:.2f} s; rest ({:.3f}, "
        "{:.3f}) m; closest approach {:.4f} m\n",
        out.sunk ? "SUNK" : "missed", sys.field().name, spec.angle, spec.speed,
        sim::to_string(out.end), out.duration, out.rest_position[0], out.rest_position[1],
        out.closest_approach);
    return;
  }
  fmt::print(
      "{} on {} (arm): angle {:.4f} rad, club {:.3f} m/s -> launch {:.4f} rad, {:.3f} m/s; "
      "{} after {:.2f} s; rest ({:.3f}, {:.3f}) m; closest approach {:.4f} m; core update "
      "p99 {:.1f} us\n",
      out.sunk ? "SUNK" : "missed", sys.field().name, spec.angle, r.club.speed, r.launch.angle,
      r.launch.speed, sim::to_string(out.end), out.duration, out.rest_position[0],
      out.rest_position[1], out.closest_approach, r.timing.core_update_p99_us);
}

}  // namespace

void add_putt_command(CLI::App& app) {
  struct Options {
    std::string field = "flat";
    std::string hole;
    std::string ball;
    std::optional<double> aim;
    bool world = false;
    double angle = 0.0;
    double speed = 0.0;
    double max_duration = system::PuttSpec{}.max_duration;
    bool ball_only = false;
    bool json = false;
    std::string trajectory;
    std::string hitting_model;
    std::string config;
    std::string plant;
    PerceptionArgs eyes;
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
  cmd->add_flag("--world", o->world,
                "With the arm: --angle is a world direction; the base faces +x when the fixed arm "
                "can make the hit, else turns to it (the stance rule of learned hits)");
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
                  "from the club's first contact)")
      ->check(output_file());
  cmd->add_option("--hitting-model", o->hitting_model,
                  "Hitting DS model file (default: data/models/hitting-default.json)");
  cmd->add_option("--config", o->config,
                  "Module config YAML (gains, envelope, ...; see notes/control.md)");
  cmd->add_option("--plant", o->plant, kPlantHelp);
  add_perception_options(cmd, o->eyes);
  cmd->callback([o] {
    system::PuttSpec spec;
    spec.angle = o->angle;
    spec.speed = o->speed;
    spec.ball_only = o->ball_only;
    spec.aim = o->aim;
    spec.world = o->world;
    spec.max_duration = o->max_duration;
    spec.record_interval = o->trajectory.empty() ? 0.0 : system::kTrajectoryInterval;
    if (o->ball_only && o->aim)
      throw InputError("--aim: only with the arm (a ball-only putt's --angle is its aim)");
    if (o->world && (o->aim || o->ball_only))
      throw InputError("--world: picks its own stance (not with --aim or --ball-only)");
    if (!o->hole.empty()) spec.hole = parse_vector<2>("--hole", o->hole);
    if (!o->ball.empty()) spec.ball = parse_vector<2>("--ball", o->ball);
    const system::System sys(system::load_config(o->config, o->field, o->hitting_model),
                             load_plant_arg(o->plant));
    if (spec.ball) system::check_ball_position(sys.field(), *spec.ball, "--ball");
    system::SystemData data(sys);
    std::unique_ptr<vision::CameraPerceptionSource> cameras;
    if (o->eyes.perception == "camera" && o->ball_only)
      throw InputError("--perception camera: only with the arm");
    if (auto c = load_perception(o->eyes, {&sys.arm_world().field()})) {
      cameras = std::make_unique<vision::CameraPerceptionSource>(
          std::move(c->rig), vision::StereoModel(std::move(c->calibration), sys.field()));
      spec.perception_source = cameras.get();
    }
    const system::PuttReport r = system::putt(sys, data, spec);
    if (!o->trajectory.empty()) write_file_atomic(o->trajectory, viz::trajectory_csv(r.outcome));
    if (o->json) {
      nlohmann::json j = system::putt_json(sys, spec, r);
      if (cameras && cameras->last()) {
        const auto& st = cameras->last()->stats();
        j["perception"] = {
            {"source", "camera"},
            {"frames", st.frames},
            {"ball_stereo", st.ball_stereo},
            {"ball_mono", st.ball_mono},
            {"ball_lost", st.ball_lost},
            {"ball_outliers", st.ball_outliers},
            {"cpu_ms_per_frame", st.frames ? 1000 * st.cpu_seconds / st.frames : 0.0},
            {"render_ms_per_frame", st.frames ? 1000 * st.render_seconds / st.frames : 0.0}};
      }
      fmt::print("{}\n", j.dump());
    } else
      print_text(sys, spec, r);
  });
}

}  // namespace mg::cli
