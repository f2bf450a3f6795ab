// identify --field F [--plant TRUE] [--putts N] [--seed S] [--balls SPEC] [--belief PRIOR]
//          [-o belief.yaml] [--json]
// The robot identifies the world (docs/belief.md): it plays N informative putts with the arm in
// the true world (the plant builds it; the estimate never reads it), perceives each ball path
// with the plant's vision error, and fits its belief: the green (rolling resistance, tilt) from
// the paths, the arm (club speed scale, launch angle bias) from its measured club speeds and
// the launch directions it saw against its own model's. Prints a table, or the belief as JSON;
// -o writes the belief file.
#include <cmath>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "belief/belief.hpp"
#include "belief/residuals.hpp"
#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/perception_args.hpp"
#include "cli/progress.hpp"
#include "core/io.hpp"
#include "experiments/identify.hpp"
#include "system/system.hpp"

namespace mg::cli {
namespace {

using experiments::Identification;
using experiments::IdentifyHit;

std::string std_text(double v, int precision) {
  return v > 0.0 ? fmt::format("{:.{}f}", v, precision) : std::string("-");
}

void print_table(const system::System& truth, const std::vector<IdentifyHit>& hits,
                 const Identification& id, const std::optional<belief::Belief>& prior,
                 const std::string& plant_path) {
  const field::Field& f = truth.field();
  fmt::print("identify on {}: {} putts with the arm in {}\n", f.name, hits.size(),
             plant_path.empty() ? "the robot's own model of the world (no --plant)"
                                : fmt::format("the true world of {}", plant_path));
  fmt::print("{:>4}  {:>16}  {:>9}  {:>9}  {:>9}  {:>8}  {:>9}  {:>9}\n", "putt", "ball [m]",
             "angle", "club cmd", "reached", "rolling", "fit rms", "launch");
  fmt::print("{:>4}  {:>16}  {:>9}  {:>9}  {:>9}  {:>8}  {:>9}  {:>9}\n", "", "", "[rad]", "[m/s]",
             "[m/s]", "samples", "[mm]", "err [mrad]");
  std::size_t obs = 0;
  for (std::size_t k = 0; k < hits.size(); ++k) {
    const IdentifyHit& h = hits[k];
    const belief::PathFit& p = id.green.paths[k];
    std::string launch = "-";
    if (h.hit && obs < id.observations.size()) {
      const auto& o = id.observations[obs++];
      if (std::isfinite(o.observed_launch_angle) && std::isfinite(o.predicted_launch_angle))
        launch = fmt::format("{:.2f}", 1e3 * (o.observed_launch_angle - o.predicted_launch_angle));
    }
    fmt::print("{:>4}  {:>16}  {:>9.4f}  {:>9.3f}  {:>9}  {:>8}  {:>9}  {:>9}\n", k + 1,
               fmt::format("({:.3f}, {:.3f})", h.situation.ball[0], h.situation.ball[1]), h.angle,
               h.speed, h.hit ? fmt::format("{:.3f}", h.reached_speed) : "no hit",
               p.used ? fmt::format("{}", p.last - p.first) : "none",
               p.used ? fmt::format("{:.2f}", 1e3 * p.rms_residual) : "-", launch);
  }
  const belief::Belief& b = id.belief;
  const plant::Plant& e = b.estimate;
  const plant::Plant& s = b.std;
  const plant::Plant before = prior ? prior->estimate : plant::Plant{};
  fmt::print("\nbelief after {} putts{}:\n", b.putts,
             prior ? fmt::format(" ({} of them the prior's)", prior->putts) : "");
  fmt::print("  {:<26} {:>12} {:>12} {:>12}\n", "key", "estimate", "std", "before");
  fmt::print("  {:<26} {:>12.5f} {:>12} {:>12.5f}\n", "field.rolling_resistance",
             *e.field.rolling_resistance, std_text(s.field.rolling_resistance.value_or(0.0), 5),
             plant::true_rolling_resistance(f, before));
  for (std::size_t i = 0; i < 2; ++i)
    fmt::print("  {:<26} {:>12.6f} {:>12} {:>12.6f}\n", fmt::format("field.extra_slope[{}]", i),
               e.field.extra_slope[i], std_text(s.field.extra_slope[i], 6),
               before.field.extra_slope[i]);
  fmt::print("  {:<26} {:>12.6f} {:>12} {:>12.6f}\n", "arm.launch_angle_bias [rad]",
             e.arm.launch_angle_bias, std_text(s.arm.launch_angle_bias, 6),
             before.arm.launch_angle_bias);
  fmt::print("  {:<26} {:>12.5f} {:>12} {:>12.5f}\n", "arm.club_speed_scale",
             e.arm.club_speed_scale, std_text(s.arm.club_speed_scale, 5),
             before.arm.club_speed_scale);
  fmt::print(
      "  field.hole_offset          [{:.4f}, {:.4f}] m: not identified (paths that miss do not "
      "show where the hole is; the prior's, std {})\n",
      e.field.hole_offset[0], e.field.hole_offset[1],
      s.field.hole_offset[0] > 0.0 || s.field.hole_offset[1] > 0.0
          ? fmt::format("[{}, {}]", s.field.hole_offset[0], s.field.hole_offset[1])
          : std::string("unknown"));
  fmt::print("  {:<26} {:>12.5f} {:>12} {:>12.5f}\n", "perception.noise [m]", e.perception.noise,
             std_text(s.perception.noise, 5), before.perception.noise);
  fmt::print("  field.sliding_friction     {:.4f}: not identified (the survey's or the prior's)\n",
             plant::true_sliding_friction(f, e));
  fmt::print(
      "green: {} of {} paths, {} rolling samples, rms residual {:.2f} mm, {} steps; arm: {} "
      "club speeds, {} launch directions; CPU: fits {:.1f} ms, the robot's model hits {:.0f} ms\n",
      id.green.paths_used, hits.size(), id.green.samples_used, 1e3 * id.green.rms_residual,
      id.green.iterations, id.arm.speed_observations, id.arm.angle_observations, 1e3 * id.fit_cpu,
      1e3 * id.predict_cpu);
  const belief::ResidualSummary r = belief::summarize_residuals(id.green);
  fmt::print(
      "residual: {:.2f} mm along the paths, {:.2f} mm across, lag-1 autocorrelation {:.2f}: {}\n",
      1e3 * r.rms_along, 1e3 * r.rms_across, r.lag1,
      r.structured ? "structured, the green differs from the survey in ways one rolling "
                     "resistance and one tilt cannot express (docs/belief.md)"
                   : "white, as vision error");
  if (b.putts == 1 || id.arm.angle_observations < 2)
    fmt::print(
        "note: one putt leaves the launch bias against a cross slope and the arm's std open; "
        "play more putts\n");
}

}  // namespace

void add_identify_command(CLI::App& app) {
  struct Args {
    std::string field = "flat";
    std::string config, hitting_model, plant, balls, prior, out;
    int putts = 5;
    std::uint64_t seed = 1;
    bool json = false;
    PerceptionArgs eyes;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "identify",
      "The robot identifies the world from its own putts: a belief file (docs/belief.md)");
  cmd->add_option("--field", a->field, "Shipped field name or path to a field file (the survey)")
      ->capture_default_str();
  cmd->add_option("--config", a->config, "Module config YAML");
  cmd->add_option("--hitting-model", a->hitting_model,
                  "Hitting DS model file (default: the shipped one)");
  cmd->add_option("--plant", a->plant,
                  "Plant file: the true world the putts are played in (never read for the "
                  "estimate; default: the robot's model)");
  cmd->add_option("--putts", a->putts, "Identification putts the robot plays")
      ->check(CLI::Range(1, 200))
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Seed of the vision's error (and of --balls)")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--balls", a->balls,
                  "Where the balls lie (a region as collect --balls; default: the tee)");
  cmd->add_option("--belief", a->prior,
                  "Prior belief file: the fit's prior (MAP), its hole offset and sliding "
                  "friction kept");
  cmd->add_option("-o,--output", a->out, "Belief YAML file to write");
  cmd->add_flag("--json", a->json, "Print the belief as JSON instead of the table");
  add_perception_options(cmd, a->eyes);
  cmd->callback([a] {
    // Every input before any work: the output, the field, the plant, the prior, the balls.
    if (!a->out.empty()) check_output_file(a->out);
    const control::ModuleConfig config = system::load_config(a->config, a->field, a->hitting_model);
    const plant::Plant plant = load_plant_arg(a->plant);
    std::optional<belief::Belief> prior;
    if (!a->prior.empty()) prior = belief::load_belief(a->prior);
    field::Field lane = field::load_field(config.field);
    const field::Field seen = plant::true_field(lane, plant);
    system::PerceptionFactory eyes = perception_factory(a->eyes, {&seen});
    // The robot's own putts (the belief's model of them is made without cameras: it imagines).
    const system::System truth(config, std::move(lane), plant, {}, std::move(eyes));
    const field::Field& surveyed = truth.field();
    if (prior) (void)belief::believed_field(surveyed, *prior);  // applies to this field
    std::vector<IdentifyHit> hits =
        experiments::plan_identification(truth, a->putts, a->balls, a->seed);

    Progress bar("identify", a->putts);
    experiments::play_identification(truth, hits, plant.perception.noise, a->seed,
                                     [&bar](int done) { bar.update(done); });
    bar.finish();
    const Identification id =
        experiments::identify_belief(config, surveyed, hits, hits.size(), prior);
    if (!a->out.empty()) write_file_atomic(a->out, belief::belief_to_yaml(id.belief));
    if (a->json) {
      nlohmann::json j = belief::belief_to_json(id.belief, surveyed);
      const belief::ResidualSummary r = belief::summarize_residuals(id.green);
      j["residual"] = {{"samples", r.samples},
                       {"rms_along", r.rms_along},
                       {"rms_across", r.rms_across},
                       {"lag1", r.lag1},
                       {"structured", r.structured}};
      fmt::print("{}\n", j.dump(2));
      return;
    }
    print_table(truth, hits, id, prior, a->plant);
    if (!a->out.empty()) fmt::print("wrote {}\n", a->out);
  });
}

}  // namespace mg::cli
