#include "game/planner.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "sim/fast_putt.hpp"
#include "sim/putt.hpp"
#include "system/parallel.hpp"

namespace mg::game {
namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap(double a) { return std::remainder(a, 2.0 * kPi); }

/// A block of the launch grid: angles x speeds, outcomes row-major by angle.
struct Block {
  std::vector<double> angles;
  std::vector<double> speeds;
  std::vector<Imagined> out;
  bool bank = false;
  const Imagined& at(std::size_t i, std::size_t j) const { return out[i * speeds.size() + j]; }
};

std::vector<double> speed_ladder(const PlannerOptions& o, int every = 1) {
  std::vector<double> s;
  const double q = std::pow(o.speed_max / o.speed_min, 1.0 / (o.speeds - 1));
  for (int j = 0; j < o.speeds; j += every) s.push_back(o.speed_min * std::pow(q, j));
  return s;
}

void run_block(const system::System& system, const LaneRegion& region, std::array<double, 2> ball,
               std::array<double, 2> hole, Block& b, const PlannerOptions& o, ImaginedCache* cache,
               int& simulated) {
  std::vector<std::array<double, 2>> launches;
  launches.reserve(b.angles.size() * b.speeds.size());
  for (double a : b.angles)
    for (double s : b.speeds) launches.push_back({wrap(a), s});
  int n = 0;
  b.out = imagine(system, region, ball, hole, launches, o, cache, &n);
  simulated += n;
}

/// What makes one ball world differ from another (its field, its plant, its model), hashed
/// (FNV-1a, 64 bits as two exact doubles): cache keys hold it, never an address or a per-object
/// number, so the same world rebuilt for another seed meets the same entries.
std::array<double, 2> world_identity(const system::System& system) {
  const sim::World& w = system.ball_world();
  const field::Field& f = w.field();
  std::string text = f.name + '\n' + f.source + '\n' + system.plant().hash + '\n' + w.mjcf();
  text += fmt::format("{} {} {}\n", f.rolling_resistance, f.sliding_friction, f.ball.radius);
  const auto& b = f.bounds;  // the surface itself (a plant may tilt it): heights on a grid
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      text += fmt::format("{} ",
                          f.height(b[0] + (b[1] - b[0]) * i / 8.0, b[2] + (b[3] - b[2]) * j / 8.0));
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ull;
  return {static_cast<double>(h >> 32), static_cast<double>(h & 0xffffffffull)};
}

/// `club` with its advance shortened (by quarters, to none) until the ball's launch point lies on
/// the lane and clear of every obstacle: next to a wall the ball meets it in the club's first
/// centimetres, which the imagined putt then simulates.
sim::ClubLaunch clear_of_walls(const field::Field& f, std::array<double, 2> ball, double angle,
                               sim::ClubLaunch club) {
  const double r = f.ball.radius, full = club.advance;
  for (int quarters = 4; quarters >= 0; --quarters) {
    club.advance = full * quarters / 4.0;
    const std::array<double, 2> p{ball[0] + club.advance * std::cos(angle),
                                  ball[1] + club.advance * std::sin(angle)};
    bool clear = p[0] >= f.bounds[0] + r && p[0] <= f.bounds[1] - r && p[1] >= f.bounds[2] + r &&
                 p[1] <= f.bounds[3] - r;
    for (const auto& o : f.obstacles) clear = clear && o.distance(p) >= r;
    if (clear) return club;
  }
  return club;  // advance 0: the ball's own position, on the lane
}

/// How many cells either side a launch error of `sigma_cells` cells reaches (2 sigma, at most 6).
int error_radius(double sigma_cells) {
  return std::min(6, static_cast<int>(std::ceil(2.0 * sigma_cells)));
}

/// Expected strokes and sink probability of cell (i, j) under the launch error.
std::pair<double, double> score(const field::Field& field, const Block& b, std::size_t i,
                                std::size_t j, const LaunchError& e) {
  const double da = b.angles.size() > 1 ? std::abs(b.angles[1] - b.angles[0]) : 1.0;
  const double dls = b.speeds.size() > 1 ? std::log(b.speeds[1] / b.speeds[0]) : 1.0;
  const double sa = e.angle / da, ss = e.speed / dls;  // the error in cells
  const int ra = error_radius(sa), rs = error_radius(ss);
  double wsum = 0.0, miss = 0.0, sink = 0.0;
  for (int di = -ra; di <= ra; ++di)
    for (int dj = -rs; dj <= rs; ++dj) {
      const long ii = static_cast<long>(i) + di, jj = static_cast<long>(j) + dj;
      if (ii < 0 || jj < 0 || ii >= static_cast<long>(b.angles.size()) ||
          jj >= static_cast<long>(b.speeds.size()))
        continue;
      const double w = (sa > 0 ? std::exp(-0.5 * di * di / (sa * sa)) : (di == 0 ? 1.0 : 0.0)) *
                       (ss > 0 ? std::exp(-0.5 * dj * dj / (ss * ss)) : (dj == 0 ? 1.0 : 0.0));
      if (w <= 0.0) continue;
      const Imagined& m = b.at(static_cast<std::size_t>(ii), static_cast<std::size_t>(jj));
      wsum += w;
      if (m.sunk)
        sink += w;
      else
        miss += w * strokes_to_go(field, m.rest, m.left_lane);
    }
  return {1.0 + miss / wsum, sink / wsum};
}

}  // namespace

void PlannerOptions::validate() const {
  system::check_threads(threads);
  require_in_range("planner.speed_min", speed_min, 0.05, 10.0);
  require_in_range("planner.speed_max", speed_max, speed_min, 10.0);
  if (speeds < 2 || speeds > 200) throw InputError("planner.speeds: expected 2..200 launch speeds");
  require_in_range("planner.accept_probability", accept_probability, 0.0, 1.0);
}

bool ImaginedCache::find(const Key& key, Imagined& out) const {
  std::lock_guard lock(mutex_);
  const auto it = map_.find(key);
  if (it == map_.end()) return false;
  out = it->second;
  return true;
}

void ImaginedCache::store(const Key& key, const Imagined& value) {
  std::lock_guard lock(mutex_);
  map_.emplace(key, value);
}

std::vector<Imagined> imagine(const system::System& system, const LaneRegion& region,
                              std::array<double, 2> ball, std::array<double, 2> hole,
                              const std::vector<std::array<double, 2>>& launches,
                              const PlannerOptions& options, ImaginedCache* cache, int* simulated) {
  const auto world_id = world_identity(system);
  std::vector<sim::PuttRequest> requests(launches.size());
  std::vector<ImaginedCache::Key> keys(launches.size());
  for (std::size_t k = 0; k < launches.size(); ++k) {
    sim::PuttRequest& r = requests[k];
    r.angle = launches[k][0];
    r.speed = launches[k][1];
    r.start = ball;
    if (options.club_launch)
      r.club = clear_of_walls(system.field(), ball, r.angle, options.club_launch(r.speed));
    const auto& c = r.club;
    keys[k] = {world_id[0],      world_id[1], ball[0],   ball[1],   r.angle,
               r.speed,          hole[0],     hole[1],   c.advance, c.lift,
               c.vertical_speed, c.spin[0],   c.spin[1], c.spin[2]};
  }
  std::vector<Imagined> out(launches.size());
  std::vector<int> todo;
  for (std::size_t k = 0; k < launches.size(); ++k)
    if (cache == nullptr || !cache->find(keys[k], out[k])) todo.push_back(static_cast<int>(k));
  const sim::World& world = system.ball_world();
  system::parallel_for(system, static_cast<int>(todo.size()), system::thread_count(options.threads),
                       [&](int t, system::SystemData& data) {
                         const auto k = static_cast<std::size_t>(todo[static_cast<std::size_t>(t)]);
                         const sim::PuttOutcome p =
                             sim::fast_putt(world, data.ball.get(), hole, requests[k]);
                         Imagined m;
                         m.sunk = p.sunk;
                         m.left_lane = p.end == sim::PuttEnd::kLeftLane ||
                                       (!p.sunk && !region.contains(p.rest_position));
                         m.rest = p.rest_position;
                         m.closest_approach = p.closest_approach;
                         out[k] = m;
                       });
  if (cache != nullptr)
    for (int k : todo)
      cache->store(keys[static_cast<std::size_t>(k)], out[static_cast<std::size_t>(k)]);
  if (simulated != nullptr) *simulated = static_cast<int>(todo.size());
  return out;
}

double strokes_to_go(const field::Field& field, std::array<double, 2> rest, bool left_lane) {
  const auto& h = field.hole.position;
  const double d = std::hypot(h[0] - rest[0], h[1] - rest[1]);
  double v = 1.0 + 0.05 * d;
  if (line_blocked(field, rest, h, field.ball.radius)) v += 1.0;
  if (left_lane) v += 1.0;
  return v;
}

namespace {

/// A cell of a coarse block, scored.
struct Candidate {
  double expected = 0.0, probability = 0.0, angle = 0.0, speed = 0.0;
  bool bank = false;
};

bool better(double e, double p, double best_e, double best_p) {
  // Ties: the more certain sink.
  return e < best_e - 1e-12 || (std::abs(e - best_e) <= 1e-12 && p > best_p);
}

/// The fine block around a candidate: spacing half the launch error (at least 0.5 mrad and
/// 0.2 %), kRefineHalfCells either side.
Block fine_block(const Candidate& c, const LaunchError& e) {
  Block f;
  const double da = std::clamp(e.angle / 2.0, kRefineAngleMin, kFineStep / 2.0);
  const double ds = std::clamp(e.speed / 2.0, kRefineSpeedMin, 0.01);
  for (int i = -kRefineHalfCells; i <= kRefineHalfCells; ++i) f.angles.push_back(c.angle + i * da);
  for (int j = -kRefineHalfCells; j <= kRefineHalfCells; ++j)
    f.speeds.push_back(c.speed * std::exp(j * ds));
  f.bank = c.bank;
  return f;
}

}  // namespace

LaunchJudgement judge_launch(const system::System& system, std::array<double, 2> ball,
                             std::array<double, 2> hole, double angle, double speed,
                             const LaunchError& error, const PlannerOptions& options,
                             ImaginedCache* cache) {
  options.validate();
  require_finite("launch angle", angle);
  require_in_range("launch speed", speed, 0.0, 10.0);
  const field::Field& field = system.field();
  system::check_ball_position(field, ball, "ball");
  field::check_hole_position(field, hole);
  const LaneRegion region(field, hole);
  Block f = fine_block({0.0, 0.0, angle, speed, false}, error);
  LaunchJudgement j;
  run_block(system, region, ball, hole, f, options, cache, j.imagined_putts);
  const auto [e, p] = score(field, f, kRefineHalfCells, kRefineHalfCells, error);
  j.expected_strokes = e;
  j.sink_probability = p;
  return j;
}

StrokePlan plan_stroke(const system::System& system, std::array<double, 2> ball,
                       std::array<double, 2> hole, const LaunchError& error,
                       const PlannerOptions& options, ImaginedCache* cache) {
  options.validate();
  require_in_range("launch error angle", error.angle, 0.0, 0.5);
  require_in_range("launch error speed", error.speed, 0.0, 0.5);
  const field::Field& field = system.field();
  system::check_ball_position(field, ball, "ball");
  field::check_hole_position(field, hole);
  const LaneRegion region(field, hole);
  int simulated = 0;
  std::vector<Candidate> cells;  // every coarse cell, scored on its own grid
  double best_p = 0.0;
  const auto collect = [&](const Block& b, bool sinks_only_refined) {
    for (std::size_t i = 0; i < b.angles.size(); ++i)
      for (std::size_t j = 0; j < b.speeds.size(); ++j) {
        const auto [e, p] = score(field, b, i, j, sinks_only_refined ? LaunchError{} : error);
        cells.push_back({e, p, wrap(b.angles[i]), b.speeds[j], b.bank});
        best_p = std::max(best_p, p);
      }
  };
  const double direct = std::atan2(hole[1] - ball[1], hole[0] - ball[0]);
  Block d;
  const int k = static_cast<int>(std::lround(kDirectSpan / kFineStep));
  for (int i = -k; i <= k; ++i) d.angles.push_back(direct + i * kFineStep);
  d.speeds = speed_ladder(options);
  run_block(system, region, ball, hole, d, options, cache, simulated);
  collect(d, false);
  if (best_p < options.accept_probability) {
    // All round, coarse (exact execution assumed there: its cells are too far apart to smooth
    // over): lay-ups, and the directions whose paths came nearest the hole.
    Block c;
    const int n = static_cast<int>(std::lround(2.0 * kPi / kCoarseStep));
    for (int i = 0; i < n; ++i) c.angles.push_back(direct + kPi * (2.0 * i / n - 1.0));
    c.speeds = speed_ladder(options, 2);
    c.bank = true;
    run_block(system, region, ball, hole, c, options, cache, simulated);
    collect(c, true);
    std::vector<std::pair<double, double>> near;  // (closest approach, angle)
    for (std::size_t i = 0; i < c.angles.size(); ++i) {
      if (std::abs(wrap(c.angles[i] - direct)) < kDirectSpan) continue;
      double m = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < c.speeds.size(); ++j)
        m = std::min(m, c.at(i, j).closest_approach);
      near.push_back({m, c.angles[i]});
    }
    std::sort(near.begin(), near.end());
    std::vector<double> centres;
    for (const auto& [m, a] : near) {
      if (static_cast<int>(centres.size()) >= kRefineRegions || m > 0.25) break;
      bool separate = true;
      for (double x : centres) separate = separate && std::abs(wrap(a - x)) > 2.0 * kRefineSpan;
      if (separate) centres.push_back(a);
    }
    for (double centre : centres) {
      Block r;
      const int kr = static_cast<int>(std::lround(kRefineSpan / kFineStep));
      for (int i = -kr; i <= kr; ++i) r.angles.push_back(centre + i * kFineStep);
      r.speeds = speed_ladder(options);
      r.bank = true;
      run_block(system, region, ball, hole, r, options, cache, simulated);
      collect(r, false);
    }
  }
  // The best coarse cells, apart from each other, each judged again on a fine grid at the scale
  // of the launch error: a coarse cell that sinks may sit on a window's edge.
  std::stable_sort(cells.begin(), cells.end(), [](const Candidate& a, const Candidate& b) {
    return better(a.expected, a.probability, b.expected, b.probability);
  });
  std::vector<Candidate> picked;
  for (const Candidate& c : cells) {
    if (static_cast<int>(picked.size()) >= kCandidates) break;
    bool apart = true;
    for (const Candidate& q : picked)
      apart = apart && (std::abs(wrap(c.angle - q.angle)) > 2.0 * kFineStep ||
                        std::abs(std::log(c.speed / q.speed)) > 0.05);
    if (apart) picked.push_back(c);
  }
  StrokePlan best;
  best.expected_strokes = std::numeric_limits<double>::infinity();
  for (const Candidate& c : picked) {
    Block f = fine_block(c, error);
    run_block(system, region, ball, hole, f, options, cache, simulated);
    // Only cells whose error neighbourhood lies inside the block are judged.
    const int ra = error_radius(error.angle / std::abs(f.angles[1] - f.angles[0]));
    const int rs = error_radius(error.speed / std::log(f.speeds[1] / f.speeds[0]));
    for (int i = ra; i < static_cast<int>(f.angles.size()) - ra; ++i)
      for (int j = rs; j < static_cast<int>(f.speeds.size()) - rs; ++j) {
        const auto [e, p] =
            score(field, f, static_cast<std::size_t>(i), static_cast<std::size_t>(j), error);
        if (better(e, p, best.expected_strokes, best.sink_probability)) {
          best.angle = wrap(f.angles[i]);
          best.speed = f.speeds[j];
          best.expected_strokes = e;
          best.sink_probability = p;
          best.bank = f.bank;
        }
      }
  }
  best.imagined_putts = simulated;
  return best;
}

}  // namespace mg::game
