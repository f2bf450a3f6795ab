#include "game/report.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::game {
namespace {

/// Mean and the half width of its 95 % interval (normal approximation; 0 for one value).
std::pair<double, double> mean_ci(const std::vector<double>& v) {
  if (v.empty()) return {0.0, 0.0};
  const auto n = static_cast<double>(v.size());
  const double m = std::accumulate(v.begin(), v.end(), 0.0) / n;
  if (v.size() < 2) return {m, 0.0};
  double ss = 0.0;
  for (double x : v) ss += (x - m) * (x - m);
  return {m, 1.96 * std::sqrt(ss / (n - 1.0) / n)};
}

int player_index(const CourseRounds& c, Player p) {
  const auto it = std::find(c.players.begin(), c.players.end(), p);
  return it == c.players.end() ? -1 : static_cast<int>(it - c.players.begin());
}

/// Strokes of every hole of every seed of `p` (course-major, then seed, then hole).
std::vector<double> hole_strokes(const std::vector<CourseRounds>& all, Player p) {
  std::vector<double> v;
  for (const auto& c : all) {
    const int i = player_index(c, p);
    if (i < 0) continue;
    for (const auto& r : c.rounds[static_cast<std::size_t>(i)])
      for (const auto& h : r.holes) v.push_back(h.strokes);
  }
  return v;
}

}  // namespace

nlohmann::json round_json(const RoundResult& r) {
  nlohmann::json holes = nlohmann::json::array();
  for (const auto& h : r.holes) {
    nlohmann::json putts = nlohmann::json::array();
    for (const auto& p : h.putts)
      putts.push_back({{"ball", p.ball},
                       {"angle", p.angle},
                       {"speed", p.speed},
                       {"launch", p.launch},
                       {"rest", p.rest},
                       {"sunk", p.sunk},
                       {"left_lane", p.left_lane},
                       {"bank", p.bank},
                       {"model", p.model},
                       {"sink_probability", p.sink_probability}});
    holes.push_back({{"field", h.field},
                     {"par", h.par},
                     {"strokes", h.strokes},
                     {"sunk", h.sunk},
                     {"putts", putts}});
  }
  return {{"course", r.course},
          {"player", to_string(r.player)},
          {"holes", holes},
          {"total_strokes", r.total_strokes},
          {"total_par", r.total_par},
          {"learning_putts", r.learning_putts},
          {"imagined_putts", r.imagined_putts}};
}

std::string round_csv(const RoundResult& r) {
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

CourseRounds play_seeds(const Course& course, const control::ModuleConfig& config,
                        const plant::Plant& plant, const std::vector<Player>& players,
                        const RoundOptions& base, std::uint64_t first_seed, int seeds,
                        const std::function<void(int, int)>& progress) {
  if (seeds < 1 || seeds > 1000)
    throw InputError(fmt::format("seeds: expected 1..1000, got {}", seeds));
  if (players.empty()) throw InputError("players: expected at least one player");
  CourseRounds c{course, players, std::vector<std::vector<RoundResult>>(players.size())};
  ImaginedCache cache;
  const int total = static_cast<int>(players.size()) * seeds;
  int done = 0;
  for (std::size_t p = 0; p < players.size(); ++p)
    for (int s = 0; s < seeds; ++s) {
      RoundOptions o = base;
      o.player = players[p];
      o.seed = first_seed + static_cast<std::uint64_t>(s);
      c.rounds[p].push_back(play_round(course, config, plant, o, &cache));
      if (progress) progress(++done, total);
    }
  return c;
}

std::vector<Player> comparison_players() {
  return {Player::kRobot, Player::kOracle, Player::kExactOracle, Player::kGreedy};
}

PlayerSummary summarize(const std::vector<CourseRounds>& all, Player player) {
  PlayerSummary s;
  s.player = player;
  std::vector<double> strokes, vs_par;
  int aces = 0, learning = 0, fields = 0;
  for (const auto& c : all) {
    const int i = player_index(c, player);
    if (i < 0) continue;
    for (const auto& r : c.rounds[static_cast<std::size_t>(i)]) {
      learning += r.learning_putts;
      fields += static_cast<int>(r.holes.size());
      for (const auto& h : r.holes) {
        strokes.push_back(h.strokes);
        vs_par.push_back(h.strokes - h.par);
        aces += h.sunk && h.strokes == 1;
        s.finished += h.sunk;
      }
    }
  }
  s.holes = static_cast<int>(strokes.size());
  std::tie(s.strokes, s.strokes_ci) = mean_ci(strokes);
  std::tie(s.vs_par, s.vs_par_ci) = mean_ci(vs_par);
  s.hole_in_one = s.holes > 0 ? static_cast<double>(aces) / s.holes : 0.0;
  // A hole's field is learned afresh each round: learning putts per (round, hole).
  s.learning_putts_per_field = fields > 0 ? static_cast<double>(learning) / fields : 0.0;
  return s;
}

std::string comparison_markdown(const std::vector<CourseRounds>& all, int seeds,
                                const std::string& plant_note) {
  if (all.empty()) return "";
  std::vector<Player> players = all.front().players;
  int holes = 0, par = 0;
  std::vector<std::string> names;
  for (const auto& c : all) {
    holes += static_cast<int>(c.course.holes.size());
    for (const auto& h : c.course.holes) par += h.par;
    names.push_back(c.course.name);
  }
  std::string md = fmt::format(
      "Courses {} ({} holes, par {}), {} seeds{}.\n\n"
      "| player | strokes per hole (95 % CI) | vs par | vs oracle (paired 95 % CI) | hole-in-one "
      "| finished | learning putts per field |\n|---|---|---|---|---|---|---|\n",
      fmt::join(names, ", "), holes, par, seeds, plant_note);
  const std::vector<double> oracle = hole_strokes(all, Player::kOracle);
  for (Player p : players) {
    const PlayerSummary s = summarize(all, p);
    std::string vs_oracle = "-";
    const std::vector<double> mine = hole_strokes(all, p);
    if (!oracle.empty() && mine.size() == oracle.size()) {
      std::vector<double> diff(mine.size());
      for (std::size_t k = 0; k < mine.size(); ++k) diff[k] = mine[k] - oracle[k];
      const auto [d, ci] = mean_ci(diff);
      vs_oracle = fmt::format("{:+.2f} ± {:.2f}", d, ci);
    }
    md += fmt::format(
        "| {} | {:.2f} ± {:.2f} | {:+.2f} ± {:.2f} | {} | {:.0f} % | {}/{} | {:.1f} |\n",
        to_string(p), s.strokes, s.strokes_ci, s.vs_par, s.vs_par_ci, vs_oracle,
        100.0 * s.hole_in_one, s.finished, s.holes, s.learning_putts_per_field);
  }
  md += "\nMean strokes per hole:\n\n| course | hole | field | par |";
  for (Player p : players) md += fmt::format(" {} |", to_string(p));
  md += "\n|---|---|---|---|";
  for (std::size_t k = 0; k < players.size(); ++k) md += "---|";
  md += "\n";
  for (const auto& c : all)
    for (std::size_t h = 0; h < c.course.holes.size(); ++h) {
      md += fmt::format("| {} | {} | {} | {} |", c.course.name, h + 1, c.course.holes[h].field.name,
                        c.course.holes[h].par);
      for (std::size_t p = 0; p < c.players.size(); ++p) {
        double sum = 0.0;
        for (const auto& r : c.rounds[p]) sum += r.holes[h].strokes;
        md += fmt::format(" {:.2f} |", sum / static_cast<double>(c.rounds[p].size()));
      }
      md += "\n";
    }
  return md;
}

std::string plant_comparison_markdown(const std::vector<PlantRounds>& all, int seeds) {
  if (all.empty()) return "";
  const Course& course = all.front().revising.course;
  std::vector<double> revising, kept, oracle;  // plant-major, then seed, then hole
  std::string per_plant;
  for (const auto& p : all) {
    const std::vector<CourseRounds> one{p.revising}, other{p.kept};
    const auto r = hole_strokes(one, Player::kRobot), o = hole_strokes(one, Player::kOracle),
               k = hole_strokes(other, Player::kRobot);
    if (r.size() != o.size() || r.size() != k.size())
      throw InputError("plant comparison: the players played different holes");
    const auto mean = [](const std::vector<double>& v) {
      return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / v.size();
    };
    per_plant += fmt::format("| {} | {} | {:.2f} | {:.2f} | {:.2f} |\n", p.plant, r.size(), mean(r),
                             mean(k), mean(o));
    revising.insert(revising.end(), r.begin(), r.end());
    kept.insert(kept.end(), k.begin(), k.end());
    oracle.insert(oracle.end(), o.begin(), o.end());
  }
  const auto row = [&](const std::string& who, const std::vector<double>& v) {
    std::vector<double> diff(v.size());
    int aces = 0;
    for (std::size_t h = 0; h < v.size(); ++h) {
      diff[h] = v[h] - oracle[h];
      aces += v[h] == 1.0;
    }
    const auto [m, ci] = mean_ci(v);
    const auto [d, dci] = mean_ci(diff);
    return fmt::format("| {} | {:.2f} ± {:.2f} | {:+.2f} ± {:.2f} | {:.0f} % |\n", who, m, ci, d,
                       dci, v.empty() ? 0.0 : 100.0 * aces / static_cast<double>(v.size()));
  };
  return fmt::format(
             "Course {} ({} holes) on {} worlds, {} seeds each: {} holes per player.\n\n"
             "| player | strokes per hole (95 % CI) | vs oracle (paired 95 % CI) | hole-in-one "
             "|\n|---|---|---|---|\n",
             course.name, course.holes.size(), all.size(), seeds, oracle.size()) +
         row("robot, revising its belief", revising) + row("robot, `--no-revise`", kept) +
         row("oracle (sees the plant)", oracle) +
         "\nMean strokes per hole, per world:\n\n| world | holes | robot revising | robot "
         "`--no-revise` | oracle |\n|---|---|---|---|---|\n" +
         per_plant;
}

}  // namespace mg::game
