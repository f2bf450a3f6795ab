#include "viz/round_figure.hpp"

#include <unistd.h>

#include <algorithm>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/plot.hpp"
#include "viz/figure_data.hpp"

namespace mg::viz {

namespace {

namespace fs = std::filesystem;

void check_rounds(const game::Course& course, const std::vector<game::RoundResult>& rounds) {
  if (rounds.empty()) throw InputError("plot round: no rounds to draw");
  for (std::size_t r = 0; r < rounds.size(); ++r) {
    const auto& holes = rounds[r].holes;
    if (holes.size() != course.holes.size())
      throw InputError(fmt::format("plot round: round {} has {} holes, course {} has {}", r + 1,
                                   holes.size(), course.name, course.holes.size()));
    for (std::size_t h = 0; h < holes.size(); ++h)
      if (holes[h].field != course.holes[h].field.name)
        throw InputError(fmt::format("plot round: round {}, hole {}: played on {}, expected {}",
                                     r + 1, h + 1, holes[h].field, course.holes[h].field.name));
  }
}

/// "robot", or "robot, oracle" for rounds of several players.
std::string players(const std::vector<game::RoundResult>& rounds) {
  std::vector<std::string> names;
  for (const auto& r : rounds) {
    const std::string n = game::to_string(r.player);
    if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
  }
  return fmt::format("{}", fmt::join(names, ", "));
}

}  // namespace

std::string round_strokes_csv(const std::vector<game::RoundResult>& rounds, std::size_t hole) {
  std::vector<std::vector<double>> rows;
  for (std::size_t r = 0; r < rounds.size(); ++r) {
    if (hole >= rounds[r].holes.size()) continue;
    const auto& putts = rounds[r].holes[hole].putts;
    for (std::size_t k = 0; k < putts.size(); ++k) {
      const auto& p = putts[k];
      rows.push_back({static_cast<double>(r), static_cast<double>(k + 1), p.ball[0], p.ball[1],
                      p.angle, p.speed, p.rest[0], p.rest[1], p.sunk ? 1.0 : 0.0,
                      p.left_lane ? 1.0 : 0.0});
    }
  }
  return format_csv({"round", "stroke", "ball_x", "ball_y", "angle", "speed", "rest_x", "rest_y",
                     "sunk", "left_lane"},
                    rows);
}

std::string round_paths_csv(const std::vector<game::RoundResult>& rounds, std::size_t hole) {
  std::vector<std::vector<double>> rows;
  for (std::size_t r = 0; r < rounds.size(); ++r) {
    if (hole >= rounds[r].holes.size()) continue;
    const auto& putts = rounds[r].holes[hole].putts;
    for (std::size_t k = 0; k < putts.size(); ++k)
      for (const auto& p : putts[k].path)
        rows.push_back({static_cast<double>(r), static_cast<double>(k + 1), p[0], p[1]});
  }
  return format_csv({"round", "stroke", "x", "y"}, rows);
}

double mean_hole_strokes(const std::vector<game::RoundResult>& rounds, std::size_t hole) {
  double sum = 0.0;
  int n = 0;
  for (const auto& r : rounds)
    if (hole < r.holes.size()) sum += r.holes[hole].strokes, ++n;
  return n > 0 ? sum / n : 0.0;
}

std::vector<fs::path> plot_round_holes(const game::Course& course,
                                       const std::vector<game::RoundResult>& rounds,
                                       const fs::path& out_dir, const std::string& stem,
                                       const fs::path& data_dir) {
  check_rounds(course, rounds);
  if (stem.empty() || stem.find('/') != std::string::npos)
    throw InputError(fmt::format("plot round: stem '{}': expected a file name without '/'", stem));
  ensure_output_dir(out_dir);
  const PlotDataDir dir(data_dir);
  std::vector<fs::path> written;
  for (std::size_t h = 0; h < course.holes.size(); ++h) {
    const game::CourseHole& ch = course.holes[h];
    const field::Field& f = ch.field;
    const std::string tag = fmt::format("{}-hole{}", stem, h + 1);
    const fs::path png = out_dir / (tag + ".png");
    const auto heights = dir.write(tag + "_heights.csv", heights_csv(f));
    const auto strokes = dir.write(tag + "_strokes.csv", round_strokes_csv(rounds, h));
    std::string args;
    bool any_path = false;
    for (const auto& r : rounds)
      for (const auto& p : r.holes[h].putts) any_path = any_path || !p.path.empty();
    if (any_path)
      args += " --paths " +
              shell_quote(dir.write(tag + "_paths.csv", round_paths_csv(rounds, h)).string());
    if (!f.obstacles.empty())
      args += " --obstacles " +
              shell_quote(dir.write(tag + "_obstacles.csv", obstacles_csv(f)).string());
    int sunk = 0;
    for (const auto& r : rounds) sunk += r.holes[h].sunk ? 1 : 0;
    const std::size_t n = rounds.size();
    const std::string title =
        fmt::format("{} hole {}: {}, par {} — {:.2f} strokes, mean of {} round{} ({}); sunk {}/{}",
                    course.name, h + 1, f.name, ch.par, mean_hole_strokes(rounds, h), n,
                    n == 1 ? "" : "s", players(rounds), sunk, n);
    run_plot_script(
        fmt::format("round {} {} {}{} --hole={},{} --hole-diameter {} --tee={},{} --title {}",
                    shell_quote(heights.string()), shell_quote(strokes.string()),
                    shell_quote(png.string()), args, f.hole.position[0], f.hole.position[1],
                    f.hole.diameter, f.tee[0], f.tee[1], shell_quote(title)),
        png.string());
    written.push_back(png);
  }
  return written;
}

}  // namespace mg::viz
