#include "experiments/collect.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <sstream>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "experiments/wire.hpp"
#include "system/distributed.hpp"

namespace mg::experiments {
namespace {

const std::vector<std::string> kColumns = {
    "index",        "hole_x",         "hole_y",       "xi_x",         "xi_y",
    "angle",        "speed",          "margin_angle", "margin_speed", "launch_angle",
    "launch_speed", "approach_speed", "full_putts",   "ball_putts"};

/// A ball off the tee in any situation: the file has ball_x, ball_y columns (last).
bool balls_off_tee(const std::vector<field::Situation>& situations, const field::Field& field) {
  for (const auto& s : situations)
    if (s.ball != field.tee) return true;
  return false;
}

std::vector<std::string> columns(bool with_ball) {
  std::vector<std::string> c = kColumns;
  if (with_ball) c.insert(c.end(), {"ball_x", "ball_y"});
  return c;
}

/// `repaired` < 0: the continuity pass has not run yet.
std::string format_file(const std::string& settings, const std::map<int, teacher::Example>& done,
                        bool with_ball, int repaired = -1) {
  std::vector<std::vector<double>> rows;
  std::string unplayable;
  for (const auto& [i, e] : done) {
    if (e.found) {
      rows.push_back({static_cast<double>(i), e.hole[0], e.hole[1], e.hole[0] - e.ball[0],
                      e.hole[1] - e.ball[1], e.angle, e.speed, e.margin_angle, e.margin_speed,
                      e.launch_angle, e.launch_speed, e.approach_speed,
                      static_cast<double>(e.full_putts), static_cast<double>(e.ball_putts)});
      if (with_ball) rows.back().insert(rows.back().end(), {e.ball[0], e.ball[1]});
    } else {
      unplayable +=
          fmt::format("# unplayable: index={} hole_x={} hole_y={} full_putts={} ball_putts={}{}\n",
                      i, e.hole[0], e.hole[1], e.full_putts, e.ball_putts,
                      with_ball ? fmt::format(" ball_x={} ball_y={}", e.ball[0], e.ball[1]) : "");
    }
  }
  const std::string pass =
      repaired >= 0 ? fmt::format("# continuity pass: repaired={}\n", repaired) : "";
  return "# " + settings + "\n" + format_csv(columns(with_ball), rows) + unplayable + pass;
}

/// Reads a file written by format_file: the examples by index. Throws InputError on a mismatch.
std::map<int, teacher::Example> read_existing(const std::filesystem::path& path,
                                              const std::string& settings,
                                              const std::vector<field::Situation>& situations,
                                              bool with_ball, int& repaired) {
  const std::string text = read_text_file(path);
  std::istringstream in(text);
  std::string first;
  std::getline(in, first);
  if (first != "# " + settings)
    throw InputError(
        fmt::format("--resume: {}: its settings differ from this run's:\n  file: {}\n  run:  # {}",
                    path.string(), first, settings));
  std::map<int, teacher::Example> done;
  const auto check_index = [&](double v) {
    if (v != std::floor(v) || v < 0 || v >= static_cast<double>(situations.size()))
      throw InputError(
          fmt::format("--resume: {}: index {} is not a situation of this run", path.string(), v));
    return static_cast<int>(v);
  };
  const CsvTable table = parse_csv(text, path.string());
  for (const auto& name : columns(with_ball)) table.column_index(name);
  for (const auto& row : table.rows) {
    const auto col = [&](const char* n) { return row[table.column_index(n)]; };
    teacher::Example e;
    const int i = check_index(col("index"));
    e.hole = situations[static_cast<std::size_t>(i)].hole;
    e.ball = situations[static_cast<std::size_t>(i)].ball;
    e.found = true;
    e.angle = col("angle");
    e.speed = col("speed");
    e.margin_angle = col("margin_angle");
    e.margin_speed = col("margin_speed");
    e.launch_angle = col("launch_angle");
    e.launch_speed = col("launch_speed");
    e.approach_speed = col("approach_speed");
    e.full_putts = static_cast<int>(col("full_putts"));
    e.ball_putts = static_cast<int>(col("ball_putts"));
    done[i] = e;
  }
  std::string line;
  while (std::getline(in, line)) {
    if (std::sscanf(line.c_str(), "# continuity pass: repaired=%d", &repaired) == 1) continue;
    if (line.rfind("# unplayable:", 0) != 0) continue;
    double index = -1, hx = 0, hy = 0;
    int full = 0, ball = 0;
    if (std::sscanf(line.c_str(),
                    "# unplayable: index=%lf hole_x=%lf hole_y=%lf full_putts=%d ball_putts=%d",
                    &index, &hx, &hy, &full, &ball) != 5)
      throw InputError(fmt::format("--resume: {}: malformed line '{}'", path.string(), line));
    teacher::Example e;
    const int i = check_index(index);
    e.hole = situations[static_cast<std::size_t>(i)].hole;
    e.ball = situations[static_cast<std::size_t>(i)].ball;
    e.full_putts = full;
    e.ball_putts = ball;
    done[i] = e;
  }
  return done;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// The continuity pass (see collect.hpp). Returns the number of replaced examples.
int repair_continuity(const system::System& system, const CollectOptions& options,
                      std::map<int, teacher::Example>& done) {
  const auto aim = [&](const teacher::Example& e) {
    return std::atan2(e.hole[1] - e.ball[1], e.hole[0] - e.ball[0]);
  };
  // Neighbours in (hole, ball): the distance between holes when every ball is on the tee.
  const auto distance = [](const teacher::Example& a, const teacher::Example& b) {
    return std::hypot(std::hypot(a.hole[0] - b.hole[0], a.hole[1] - b.hole[1]),
                      std::hypot(a.ball[0] - b.ball[0], a.ball[1] - b.ball[1]));
  };
  struct Job {
    int index;
    std::array<double, 2> hint;
    double deviation;  ///< of the current example (1e9: none)
  };
  std::vector<Job> jobs;
  const bool speed = options.teacher.learn_speed;
  for (const auto& [i, e] : done) {
    std::vector<std::pair<double, int>> near;
    for (const auto& [j, n] : done)
      if (j != i && n.found) near.emplace_back(distance(n, e), j);
    if (near.size() < 2) continue;
    std::sort(near.begin(), near.end());
    near.resize(std::min<std::size_t>(4, near.size()));
    std::vector<double> rel, v;
    for (const auto& [d, j] : near) {
      rel.push_back(done[j].angle - aim(done[j]));
      v.push_back(done[j].speed);
    }
    const double rel_med = median(rel), v_med = median(v);
    const double dev = e.found ? std::max(std::abs(e.angle - aim(e) - rel_med) / kAngleJump,
                                          speed ? std::abs(e.speed - v_med) / kSpeedJump : 0.0)
                               : 1e9;
    if (dev > 1.0)
      jobs.push_back({i, {aim(e) + rel_med, speed ? v_med : options.teacher.fixed_speed}, dev});
  }
  if (jobs.empty()) return 0;
  std::vector<teacher::Example> fresh(jobs.size());
  system::distributed_for(system, fresh, options.threads, [&](int k, system::SystemData& data) {
    teacher::TeacherOptions t = options.teacher;
    t.use_hint = true;
    t.hint = jobs[static_cast<std::size_t>(k)].hint;
    const teacher::Example& e = done.at(jobs[static_cast<std::size_t>(k)].index);
    fresh[static_cast<std::size_t>(k)] = teacher::teach(system, data, {e.ball, e.hole}, t);
  });
  int replaced = 0;
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    teacher::Example& old = done[jobs[k].index];
    const teacher::Example& e = fresh[k];
    const double dev = std::max(std::abs(e.angle - jobs[k].hint[0]) / kAngleJump,
                                speed ? std::abs(e.speed - jobs[k].hint[1]) / kSpeedJump : 0.0);
    const int full = old.full_putts + e.full_putts, ball = old.ball_putts + e.ball_putts;
    if (e.found && dev < jobs[k].deviation) {
      old = e;
      ++replaced;
    }
    old.full_putts = full;  // the repair's putts count whether it succeeded or not
    old.ball_putts = ball;
  }
  return replaced;
}

}  // namespace

std::string collect_settings(const system::System& system,
                             const std::vector<field::Situation>& situations,
                             const CollectOptions& o) {
  const auto& t = o.teacher;
  const auto& f = system.field();
  const field::Situation first = situations.empty() ? field::Situation{} : situations.front();
  const field::Situation last = situations.empty() ? field::Situation{} : situations.back();
  // Balls off the tee are named; a tee-only run keeps the settings line of earlier versions.
  const std::string balls = balls_off_tee(situations, f)
                                ? fmt::format(" balls=({},{})..({},{})", first.ball[0],
                                              first.ball[1], last.ball[0], last.ball[1])
                                : "";
  return fmt::format(
      "minigolf collect: field={} strategy={} outputs={} speed={} margin_angle={} margin_speed={} "
      "budget={},{} situations={} first=({},{}) last=({},{}){} seed={} hitting_model={}",
      f.name, teacher::to_string(t.strategy), t.learn_speed ? "angle,speed" : "angle",
      t.learn_speed ? 0.0 : t.fixed_speed, t.margin_angle, t.margin_speed, t.max_full_putts,
      t.max_ball_putts, situations.size(), first.hole[0], first.hole[1], last.hole[0], last.hole[1],
      balls, o.seed, std::filesystem::path(system.config().hitting_model).filename().string());
}

std::string collect_settings(const system::System& system,
                             const std::vector<std::array<double, 2>>& holes,
                             const CollectOptions& options) {
  return collect_settings(system, on_tee(system.field(), holes), options);
}

std::vector<field::Situation> on_tee(const field::Field& field,
                                     const std::vector<std::array<double, 2>>& holes) {
  std::vector<field::Situation> out;
  out.reserve(holes.size());
  for (const auto& h : holes) out.push_back({field.tee, h});
  return out;
}

CollectResult collect(const system::System& system, const std::vector<std::array<double, 2>>& holes,
                      const CollectOptions& options, const std::filesystem::path& out,
                      const std::function<void(int, int, const teacher::Example&)>& progress) {
  return collect(system, on_tee(system.field(), holes), options, out, progress);
}

CollectResult collect(const system::System& system, const std::vector<field::Situation>& situations,
                      const CollectOptions& options, const std::filesystem::path& out,
                      const std::function<void(int, int, const teacher::Example&)>& progress) {
  options.teacher.validate();
  if (situations.empty()) throw InputError("collect: expected at least one situation, got none");
  for (const auto& s : situations) {
    field::check_hole_position(system.field(), s.hole);
    field::check_ball_position(system.field(), s.ball, "collect: ball");
    system::check_real_holes(system.field(), system.plant(), {s.hole}, "collect");
  }
  const bool with_ball = balls_off_tee(situations, system.field());
  const std::string settings = collect_settings(system, situations, options);
  std::map<int, teacher::Example> done;
  std::error_code ec;
  int repaired = -1;
  if (options.resume && std::filesystem::exists(out, ec))
    done = read_existing(out, settings, situations, with_ball, repaired);
  CollectResult result;
  result.resumed = static_cast<int>(done.size());
  std::vector<int> todo;
  for (int i = 0; i < static_cast<int>(situations.size()); ++i)
    if (!done.count(i)) todo.push_back(i);
  std::vector<teacher::Example> fresh(todo.size());
  int finished = result.resumed;
  const int total = static_cast<int>(situations.size());
  if (!todo.empty())
    write_file_atomic(out, format_file(settings, done, with_ball));  // the pass reruns
  system::distributed_for(
      system, fresh, options.threads,
      [&](int k, system::SystemData& data) {
        const int i = todo[static_cast<std::size_t>(k)];
        fresh[static_cast<std::size_t>(k)] =
            teacher::teach(system, data, situations[static_cast<std::size_t>(i)], options.teacher);
      },
      [&](int k) {
        const teacher::Example& e = fresh[static_cast<std::size_t>(k)];
        done[todo[static_cast<std::size_t>(k)]] = e;
        if (system::is_root_process())
          write_file_atomic(out, format_file(settings, done, with_ball));
        if (progress) progress(++finished, total, e);
      });
  if (repaired < 0 ||
      !todo.empty()) {  // a finished file has had its pass: resuming it changes nothing
    repaired = repair_continuity(system, options, done);
    write_file_atomic(out, format_file(settings, done, with_ball, repaired));
  }
  result.repaired = repaired;
  for (const auto& [i, e] : done) {
    result.examples.push_back(e);
    result.full_putts += e.full_putts;
    result.ball_putts += e.ball_putts;
  }
  return result;
}

}  // namespace mg::experiments
