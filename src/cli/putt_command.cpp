// putt --field F --hole X,Y --angle RAD --speed M/S --ball-only [--json] [--trajectory FILE]
#include <cmath>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "field/field.hpp"
#include "sim/putt.hpp"

namespace mg::cli {

void add_putt_command(CLI::App& app) {
  struct Options {
    std::string field = "flat";
    std::string hole;
    double angle = 0.0;
    double speed = 0.0;
    double max_duration = 30.0;
    bool ball_only = false;
    bool json = false;
    std::string trajectory;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("putt", "Simulate one putt and report the outcome");
  cmd->add_option("--field", o->field, "Shipped field name or path to a field file")
      ->capture_default_str();
  cmd->add_option("--hole", o->hole, "Hole centre X,Y in metres (default: the field's)");
  cmd->add_option("--angle", o->angle, "Launch angle [rad], counter-clockwise from +x")->required();
  cmd->add_option("--speed", o->speed, "Launch speed [m/s]")->required();
  cmd->add_option("--max-duration", o->max_duration, "Give up after this simulated time [s]")
      ->capture_default_str();
  cmd->add_flag("--ball-only", o->ball_only, "Launch the ball directly (no arm)");
  cmd->add_flag("--json", o->json, "Print one JSON object");
  cmd->add_option("--trajectory", o->trajectory, "Write the ball trajectory to this CSV file");
  cmd->callback([o] {
    if (!o->ball_only)
      throw InputError("putt: the simulated arm is not part of this build yet; pass --ball-only");
    sim::PuttRequest request;
    request.angle = o->angle;
    request.speed = o->speed;
    request.max_duration = o->max_duration;
    request.record_interval = o->trajectory.empty() ? 0.0 : 0.01;
    request.validate();
    const sim::World world(field::load_field(o->field));
    const auto hole = o->hole.empty() ? world.field().hole.position : parse_vector<2>("--hole", o->hole);
    field::check_hole_position(world.field(), hole);
    auto data = world.make_data();
    const sim::PuttOutcome out = simulate_putt(world, data.get(), hole, request);

    if (!o->trajectory.empty()) {
      std::vector<std::vector<double>> rows;
      rows.reserve(out.trajectory.size());
      for (const auto& s : out.trajectory) rows.push_back({s.t, s.x, s.y, s.z, s.vx, s.vy, s.vz});
      write_file_atomic(o->trajectory, format_csv({"t", "x", "y", "z", "vx", "vy", "vz"}, rows));
    }
    if (o->json) {
      const nlohmann::json j = {
          {"field", world.field().name},
          {"hole", hole},
          {"angle", o->angle},
          {"speed", o->speed},
          {"sunk", out.sunk},
          {"end", sim::to_string(out.end)},
          {"rest_position", out.rest_position},
          {"closest_approach", out.closest_approach},
          {"duration", out.duration},
          {"steps", out.steps},
      };
      fmt::print("{}\n", j.dump());
    } else {
      fmt::print("{} on {}: angle {:.4f} rad, speed {:.3f} m/s -> {} after {:.2f} s; rest ({:.3f}, "
                 "{:.3f}) m; closest approach {:.4f} m\n",
                 out.sunk ? "SUNK" : "missed", world.field().name, o->angle, o->speed,
                 sim::to_string(out.end), out.duration, out.rest_position[0], out.rest_position[1],
                 out.closest_approach);
    }
  });
}

}  // namespace mg::cli
