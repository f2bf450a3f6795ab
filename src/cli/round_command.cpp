// play --course COURSE [--player robot|oracle|greedy] [--seed S] [--budget N] [--plant P]
//      [--config F] [--hitting-model F] [--threads N] [--json] [-o CSV]
// play --course COURSE --compare [--seeds N] [-o MARKDOWN]
// A round of minigolf (game/round.hpp, docs/play.md).
#include <cmath>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "game/round.hpp"
#include "system/system.hpp"

namespace mg::cli {
namespace {

nlohmann::json round_json(const game::RoundResult& r, const plant::Plant& plant) {
  nlohmann::json holes = nlohmann::json::array();
  for (const auto& h : r.holes) {
    nlohmann::json putts = nlohmann::json::array();
    for (const auto& p : h.putts)
      putts.push_back({{"ball", p.ball},
                       {"angle", p.angle},
                       {"speed", p.speed},
                       {"rest", p.rest},
                       {"sunk", p.sunk},
                       {"left_lane", p.left_lane},
                       {"bank", p.bank},
                       {"sink_probability", p.sink_probability}});
    holes.push_back({{"field", h.field},
                     {"par", h.par},
                     {"strokes", h.strokes},
                     {"sunk", h.sunk},
                     {"putts", putts}});
  }
  return {{"course", r.course},
          {"player", game::to_string(r.player)},
          {"plant", plant_json(plant)},
          {"holes", holes},
          {"total_strokes", r.total_strokes},
          {"total_par", r.total_par},
          {"learning_putts", r.learning_putts},
          {"imagined_putts", r.imagined_putts}};
}

std::string round_csv(const game::RoundResult& r) {
  std::string out =
      "hole,field,par,stroke,ball_x,ball_y,angle,speed,rest_x,rest_y,sunk,left_lane\n";
  for (std::size_t h = 0; h < r.holes.size(); ++h)
    for (std::size_t k = 0; k < r.holes[h].putts.size(); ++k) {
      const auto& p = r.holes[h].putts[k];
      out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", h + 1, r.holes[h].field,
                         r.holes[h].par, k + 1, p.ball[0], p.ball[1], p.angle, p.speed, p.rest[0],
                         p.rest[1], p.sunk ? 1 : 0, p.left_lane ? 1 : 0);
    }
  return out;
}

/// Mean and the half width of its 95 % interval (normal approximation; 0 for one value).
std::pair<double, double> mean_ci(const std::vector<double>& v) {
  const double n = static_cast<double>(v.size());
  const double m = std::accumulate(v.begin(), v.end(), 0.0) / n;
  if (v.size() < 2) return {m, 0.0};
  double ss = 0;
  for (double x : v) ss += (x - m) * (x - m);
  return {m, 1.96 * std::sqrt(ss / (n - 1) / n)};
}

struct Args {
  std::string course;
  std::string player = "robot";
  std::uint64_t seed = 0;
  int seeds = 5;
  int budget = 6;
  bool compare = false;
  bool json = false;
  std::string out;
  SystemArgs system;
};

void run_round(const Args& a) {
  const game::Course course = game::load_course(a.course);
  game::RoundOptions o;
  o.player = game::parse_player(a.player, "--player");
  o.seed = a.seed;
  o.calibration_putts = a.budget;
  o.planner.threads = a.system.threads;
  o.validate();
  if (!a.out.empty()) check_output_file(a.out);
  const auto config = system::load_config(a.system.config, "", a.system.hitting_model);
  const plant::Plant plant = load_plant_arg(a.system.plant);
  game::ImaginedCache cache;
  Progress progress(fmt::format("play {} ({})", course.name, a.player),
                    static_cast<int>(course.holes.size()));
  const auto r = game::play_round(
      course, config, plant, o, &cache,
      [&](int hole, const game::StrokeRecord& s) { progress.update(hole + (s.sunk ? 1 : 0)); });
  progress.finish();
  if (!a.out.empty()) write_file_atomic(a.out, round_csv(r));
  if (a.json) {
    fmt::print("{}\n", round_json(r, plant).dump());
    return;
  }
  fmt::print("{} ({}): {} strokes, par {}; {} learning putts, {} imagined putts\n", course.name,
             a.player, r.total_strokes, r.total_par, r.learning_putts, r.imagined_putts);
  for (std::size_t h = 0; h < r.holes.size(); ++h) {
    const auto& hole = r.holes[h];
    fmt::print("  hole {} {:<16} par {}  strokes {}{}\n", h + 1, hole.field, hole.par, hole.strokes,
               hole.sunk ? "" : "  (not sunk)");
  }
}

/// Every player over `seeds` seeds: the Markdown table of docs/play.md.
void run_compare(const Args& a) {
  const game::Course course = game::load_course(a.course);
  if (a.seeds < 1 || a.seeds > 1000)
    throw InputError(fmt::format("--seeds: expected 1..1000, got {}", a.seeds));
  if (!a.out.empty()) check_output_file(a.out);
  const auto config = system::load_config(a.system.config, "", a.system.hitting_model);
  const plant::Plant plant = load_plant_arg(a.system.plant);
  game::ImaginedCache cache;
  const std::vector<game::Player> players{game::Player::kRobot, game::Player::kOracle,
                                          game::Player::kGreedy};
  std::vector<std::vector<game::RoundResult>> rounds(players.size());
  Progress progress(fmt::format("play {} --compare", course.name),
                    static_cast<int>(players.size()) * a.seeds);
  int done = 0;
  for (std::size_t p = 0; p < players.size(); ++p)
    for (int s = 0; s < a.seeds; ++s) {
      game::RoundOptions o;
      o.player = players[p];
      o.seed = a.seed + static_cast<std::uint64_t>(s);
      o.calibration_putts = a.budget;
      o.planner.threads = a.system.threads;
      rounds[p].push_back(game::play_round(course, config, plant, o, &cache));
      progress.update(++done);
    }
  progress.finish();
  const std::size_t nh = course.holes.size();
  std::vector<double> oracle_per_hole;
  for (const auto& r : rounds[1])
    for (const auto& h : r.holes) oracle_per_hole.push_back(h.strokes);
  const double oracle_mean = mean_ci(oracle_per_hole).first;
  std::string md = fmt::format(
      "Course {} ({} holes, par {}), {} seeds{}.\n\n"
      "| player | strokes per hole (95 % CI) | vs par | vs oracle | hole-in-one | finished | "
      "learning putts per field |\n|---|---|---|---|---|---|---|\n",
      course.name, nh, rounds[0][0].total_par, a.seeds,
      plant.empty() ? "" : fmt::format(", plant {}", plant.source));
  for (std::size_t p = 0; p < players.size(); ++p) {
    std::vector<double> strokes, vs_par;
    int aces = 0, finished = 0, total = 0, learning = 0;
    for (const auto& r : rounds[p]) {
      learning += r.learning_putts;
      for (const auto& h : r.holes) {
        strokes.push_back(h.strokes);
        vs_par.push_back(h.strokes - h.par);
        aces += h.sunk && h.strokes == 1;
        finished += h.sunk;
        ++total;
      }
    }
    const auto [m, ci] = mean_ci(strokes);
    const auto [mp, cip] = mean_ci(vs_par);
    md += fmt::format(
        "| {} | {:.2f} ± {:.2f} | {:+.2f} ± {:.2f} | {:+.2f} | {:.0f} % | {}/{} | {:.1f} |\n",
        game::to_string(players[p]), m, ci, mp, cip, m - oracle_mean, 100.0 * aces / total,
        finished, total, static_cast<double>(learning) / (a.seeds * static_cast<double>(nh)));
  }
  md +=
      "\nPer hole (mean strokes): \n\n| hole | field | par | robot | oracle | greedy |\n"
      "|---|---|---|---|---|---|\n";
  for (std::size_t h = 0; h < nh; ++h) {
    md += fmt::format("| {} | {} | {} |", h + 1, course.holes[h].field.name, course.holes[h].par);
    for (std::size_t p = 0; p < players.size(); ++p) {
      double sum = 0;
      for (const auto& r : rounds[p]) sum += r.holes[h].strokes;
      md += fmt::format(" {:.2f} |", sum / a.seeds);
    }
    md += "\n";
  }
  if (!a.out.empty()) write_file_atomic(a.out, md);
  fmt::print("{}", md);
}

}  // namespace

void add_round_command(CLI::App& app) {
  auto a = std::make_shared<Args>();
  a->system.field = "";
  auto* cmd = app.add_subcommand("play", "Play a round of minigolf on a course (docs/play.md)");
  cmd->add_option("--course", a->course, "Shipped course name or path to a course file")
      ->required();
  cmd->add_option("--player", a->player, "robot (the arm, its own model), oracle or greedy")
      ->check(CLI::IsMember({"robot", "oracle", "greedy"}))
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Seed (vision error, execution)")->capture_default_str();
  cmd->add_option("--budget", a->budget, "The robot's learning putts per field (1..50)")
      ->check(CLI::Range(1, 50))
      ->capture_default_str();
  cmd->add_flag("--compare", a->compare, "Every player over --seeds seeds: a Markdown table");
  cmd->add_option("--seeds", a->seeds, "With --compare: seeds from --seed on")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "One JSON object (course, holes, putts, totals)");
  cmd->add_option("-o,--output", a->out, "CSV of every stroke (with --compare: the Markdown)");
  cmd->add_option("--config", a->system.config, "Module config YAML");
  cmd->add_option("--hitting-model", a->system.hitting_model,
                  "Hitting DS model file (default: the shipped one)");
  cmd->add_option("--plant", a->system.plant, kPlantHelp);
  cmd->add_option("--threads", a->system.threads,
                  "Threads (0: all cores; results do not depend on it)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd->callback([a] {
    if (a->compare && a->json) throw InputError("--json: not with --compare (a Markdown table)");
    if (a->compare)
      run_compare(*a);
    else
      run_round(*a);
  });
}

}  // namespace mg::cli
