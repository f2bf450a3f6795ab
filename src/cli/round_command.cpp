// play --course COURSE [--player robot|oracle|exact-oracle|greedy] [--learner self-teach --budget
// N]
//      [--model FIELD=FILE] [--seed S] [--plant P] [--config F] [--hitting-model F] [--threads N]
//      [--json] [-o CSV]
// play --course COURSE[,COURSE...] --compare [--seeds N] [-o MARKDOWN]
// play --course COURSE --compare --plants N [--plant STAND_IN] [--plant-seed S]
// A round of minigolf (game/round.hpp, docs/round.md).
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/perception_args.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/round_study.hpp"
#include "game/report.hpp"
#include "system/system.hpp"

namespace mg::cli {
namespace {

struct Args {
  std::vector<std::string> courses;
  std::string player = "robot";
  std::string learner = "self-teach";
  std::uint64_t seed = 0;
  int seeds = 5;
  int budget = game::RoundOptions{}.calibration_putts;
  bool compare = false;
  bool json = false;
  std::string out;
  std::vector<std::string> models;  ///< FIELD=FILE
  bool no_revise = false;
  int plants = 0;  ///< --compare over this many random plants (and --plant, if given)
  std::uint64_t plant_seed = 1;
  SystemArgs system;
  PerceptionArgs eyes;
};

game::RoundOptions round_options(const Args& a, const std::vector<game::Course>& courses,
                                 const plant::Plant& plant) {
  game::RoundOptions o;
  o.player = game::parse_player(a.player, "--player");
  o.seed = a.seed;
  o.calibration_putts = a.budget;
  o.planner.threads = a.system.threads;
  if (!a.models.empty() && o.player != game::Player::kRobot)
    throw InputError("--model: only the robot player plays a learned model");
  o.models = experiments::load_round_models(a.models, "--model");
  o.belief = load_belief_arg(a.system.belief);
  o.revise = !a.no_revise;
  // The cameras must see every lane of every course, as it really is.
  std::vector<field::Field> lanes;
  for (const auto& course : courses)
    for (const auto& hole : course.holes) lanes.push_back(plant::true_field(hole.field, plant));
  std::vector<const field::Field*> seen;
  for (const auto& lane : lanes) seen.push_back(&lane);
  o.perception = perception_factory(a.eyes, seen);
  o.validate();
  return o;
}

void run_round(const Args& a) {
  if (a.courses.size() != 1)
    throw InputError("--course: one course per round (several only with --compare)");
  const game::Course course = game::load_course(a.courses[0]);
  const plant::Plant plant = load_plant_arg(a.system.plant);
  const game::RoundOptions o = round_options(a, {course}, plant);
  if (!a.out.empty()) check_output_file(a.out);
  const auto config = system::load_config(a.system.config, "", a.system.hitting_model);
  game::ImaginedCache cache;
  Progress progress(fmt::format("play {} ({})", course.name, a.player),
                    static_cast<int>(course.holes.size()));
  const auto r = game::play_round(
      course, config, plant, o, &cache,
      [&](int hole, const game::StrokeRecord& s) { progress.update(hole + (s.sunk ? 1 : 0)); });
  progress.finish();
  if (!a.out.empty()) write_file_atomic(a.out, game::round_csv(r));
  if (a.json) {
    nlohmann::json j = game::round_json(r);
    j["plant"] = plant_json(plant);
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("{} ({}): {} strokes, par {}; {} learning putts, {} imagined putts\n", course.name,
             a.player, r.total_strokes, r.total_par, r.learning_putts, r.imagined_putts);
  if (r.belief_paths > 0)
    fmt::print(
        "  believed green after {} paths: rolling resistance x {:.4f} +- {:.4f}, tilt ({:.2f}, "
        "{:.2f}) +- ({:.2f}, {:.2f}) mrad\n",
        r.belief_paths, r.believed_green[0], r.believed_green_std[0], 1e3 * r.believed_green[1],
        1e3 * r.believed_green[2], 1e3 * r.believed_green_std[1], 1e3 * r.believed_green_std[2]);
  for (std::size_t h = 0; h < r.holes.size(); ++h) {
    const auto& hole = r.holes[h];
    fmt::print("  hole {} {:<16} par {}  strokes {}{}\n", h + 1, hole.field, hole.par, hole.strokes,
               hole.sunk ? "" : "  (not sunk)");
  }
}

/// The robot revising, the robot keeping its belief and the oracle on the stand-in (--plant) and
/// --plants random plants: docs/round.md "Rounds on unknown plants".
void run_plant_compare(const Args& a) {
  if (a.courses.size() != 1) throw InputError("--plants: one course");
  if (a.no_revise) throw InputError("--no-revise: not with --plants (it compares both)");
  const game::Course course = game::load_course(a.courses[0]);
  std::vector<std::pair<std::string, plant::Plant>> worlds;
  if (!a.system.plant.empty()) worlds.emplace_back(a.system.plant, load_plant_arg(a.system.plant));
  for (int k = 0; k < a.plants; ++k) {
    const std::uint64_t seed = a.plant_seed + static_cast<std::uint64_t>(k);
    worlds.emplace_back(fmt::format("`plant random --seed {}`", seed), plant::random_plant(seed));
  }
  // Every world's options before its first round (the cameras must see each world's lanes).
  std::vector<game::RoundOptions> options;
  for (const auto& world : worlds) options.push_back(round_options(a, {course}, world.second));
  if (!a.out.empty()) check_output_file(a.out);
  const auto config = system::load_config(a.system.config, "", a.system.hitting_model);
  const int rounds = static_cast<int>(worlds.size()) * 3 * a.seeds;
  Progress progress("play --compare --plants", rounds);
  std::vector<game::PlantRounds> all;
  for (std::size_t w = 0; w < worlds.size(); ++w) {
    const auto& [name, plant] = worlds[w];
    game::RoundOptions& base = options[w];
    const int before = static_cast<int>(all.size()) * 3 * a.seeds;
    game::PlantRounds p;
    p.plant = name;
    base.revise = true;
    p.revising =
        game::play_seeds(course, config, plant, {game::Player::kRobot, game::Player::kOracle}, base,
                         a.seed, a.seeds, [&](int done, int) { progress.update(before + done); });
    base.revise = false;
    p.kept = game::play_seeds(course, config, plant, {game::Player::kRobot}, base, a.seed, a.seeds,
                              [&](int done, int) { progress.update(before + 2 * a.seeds + done); });
    all.push_back(std::move(p));
  }
  progress.finish();
  const std::string md = game::plant_comparison_markdown(all, a.seeds);
  if (!a.out.empty()) write_file_atomic(a.out, md);
  fmt::print("{}", md);
}

/// Every player over `seeds` seeds on every course: the Markdown tables of docs/round.md.
void run_compare(const Args& a) {
  if (a.plants > 0) return run_plant_compare(a);
  std::vector<game::Course> courses;
  for (const auto& c : a.courses) courses.push_back(game::load_course(c));
  const plant::Plant plant = load_plant_arg(a.system.plant);
  const game::RoundOptions base = round_options(a, courses, plant);
  if (!a.out.empty()) check_output_file(a.out);
  const auto config = system::load_config(a.system.config, "", a.system.hitting_model);
  const std::vector<game::Player> players = game::comparison_players();
  const int rounds = static_cast<int>(courses.size() * players.size()) * a.seeds;
  Progress progress("play --compare", rounds);
  std::vector<game::CourseRounds> all;
  for (const auto& course : courses) {
    const int before = static_cast<int>(all.size() * players.size()) * a.seeds;
    all.push_back(game::play_seeds(course, config, plant, players, base, a.seed, a.seeds,
                                   [&](int done, int) { progress.update(before + done); }));
  }
  progress.finish();
  const std::string md = game::comparison_markdown(
      all, a.seeds, plant.empty() ? "" : fmt::format(", plant {}", plant.source));
  if (!a.out.empty()) write_file_atomic(a.out, md);
  fmt::print("{}", md);
}

}  // namespace

void add_round_command(CLI::App& app) {
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("play", "Play a round of minigolf on a course (docs/round.md)");
  cmd->add_option("--course", a->courses,
                  "Shipped course name or path to a course file (several, comma-separated, with "
                  "--compare)")
      ->required()
      ->delimiter(',');
  cmd->add_option("--player", a->player,
                  "robot (the arm, its own model), oracle (the true world, the arm's precision), "
                  "exact-oracle (exact execution) or greedy")
      ->check(CLI::IsMember({"robot", "oracle", "exact-oracle", "greedy"}))
      ->capture_default_str();
  cmd->add_option("--learner", a->learner,
                  "How the robot learns its skill on each field: self-teach (its own putts)")
      ->check(CLI::IsMember({"self-teach"}))
      ->capture_default_str();
  cmd->add_option("--model", a->models,
                  "FIELD=FILE: the robot's learned model (minigolf train) for the holes on FIELD; "
                  "it plays a stroke when its hit sinks surely in the robot's model of the field "
                  "(several: repeat or comma-separate)")
      ->delimiter(',');
  cmd->add_option("--seed", a->seed, "Seed (vision error, execution)")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--budget", a->budget, "The robot's learning putts per field (1..50)")
      ->check(CLI::Range(1, 50))
      ->capture_default_str();
  cmd->add_flag("--compare", a->compare,
                "Every player over --seeds seeds on every course: Markdown tables");
  cmd->add_option("--seeds", a->seeds, "With --compare: seeds from --seed on")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--plants", a->plants,
                  "With --compare: the robot revising its belief, keeping it, and the oracle on "
                  "this many random plants (and --plant, if given), one course")
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--plant-seed", a->plant_seed,
                  "With --plants: plant k is `plant random --seed "
                  "PLANT_SEED+k`")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "One JSON object (course, holes, putts, totals)");
  cmd->add_option("-o,--output", a->out, "CSV of every stroke (with --compare: the Markdown)")
      ->check(output_file());
  cmd->add_option("--config", a->system.config, "Module config YAML");
  cmd->add_option("--hitting-model", a->system.hitting_model,
                  "Hitting DS model file (default: the shipped one)");
  cmd->add_option("--plant", a->system.plant, kPlantHelp);
  cmd->add_option("--belief", a->system.belief, kBeliefHelp);
  add_perception_options(cmd, a->eyes);
  cmd->add_flag("--no-revise", a->no_revise,
                "The robot keeps its belief of the green (no revision from the balls it watches)");
  cmd->add_option("--threads", a->system.threads,
                  "Threads (0: all cores; results do not depend on it)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd->callback([a] {
    if (a->compare && a->json) throw InputError("--json: not with --compare (a Markdown table)");
    if (a->plants > 0 && !a->compare) throw InputError("--plants: only with --compare");
    if (a->compare)
      run_compare(*a);
    else
      run_round(*a);
  });
}

}  // namespace mg::cli
