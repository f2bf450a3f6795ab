#include "game/planner.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/check.hpp"
#include "core/error.hpp"
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

void run_block(const system::System& system, std::array<double, 2> ball, std::array<double, 2> hole,
               Block& b, const PlannerOptions& o, ImaginedCache* cache, int& simulated) {
  std::vector<std::array<double, 2>> launches;
  launches.reserve(b.angles.size() * b.speeds.size());
  for (double a : b.angles)
    for (double s : b.speeds) launches.push_back({wrap(a), s});
  int n = 0;
  b.out = imagine(system, ball, hole, launches, o.threads, cache, &n);
  simulated += n;
}

/// Expected strokes and sink probability of cell (i, j) under the launch error.
std::pair<double, double> score(const field::Field& field, const Block& b, std::size_t i,
                                std::size_t j, const LaunchError& e) {
  const double da = b.angles.size() > 1 ? std::abs(b.angles[1] - b.angles[0]) : 1.0;
  const double dls = b.speeds.size() > 1 ? std::log(b.speeds[1] / b.speeds[0]) : 1.0;
  const double sa = e.angle / da, ss = e.speed / dls;  // the error in cells
  const int ra = std::min(6, static_cast<int>(std::ceil(2.5 * sa)));
  const int rs = std::min(6, static_cast<int>(std::ceil(2.5 * ss)));
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
  require_in_range("planner.speed_min", speed_min, 0.05, 10.0);
  require_in_range("planner.speed_max", speed_max, speed_min, 10.0);
  if (speeds < 2 || speeds > 200) throw InputError("planner.speeds: expected 2..200 launch speeds");
  require_in_range("planner.accept_probability", accept_probability, 0.0, 1.0);
}

bool ImaginedCache::find(const std::array<double, 6>& key, Imagined& out) const {
  std::lock_guard lock(mutex_);
  const auto it = map_.find(key);
  if (it == map_.end()) return false;
  out = it->second;
  return true;
}

void ImaginedCache::store(const std::array<double, 6>& key, const Imagined& value) {
  std::lock_guard lock(mutex_);
  map_.emplace(key, value);
}

std::vector<Imagined> imagine(const system::System& system, std::array<double, 2> ball,
                              std::array<double, 2> hole,
                              const std::vector<std::array<double, 2>>& launches, int threads,
                              ImaginedCache* cache, int* simulated) {
  std::vector<Imagined> out(launches.size());
  std::vector<int> todo;
  const auto key = [&](std::size_t k) {
    return std::array<double, 6>{ball[0],        ball[1], launches[k][0],
                                 launches[k][1], hole[0], hole[1]};
  };
  for (std::size_t k = 0; k < launches.size(); ++k)
    if (cache == nullptr || !cache->find(key(k), out[k])) todo.push_back(static_cast<int>(k));
  const sim::World& world = system.ball_world();
  system::parallel_for(system, static_cast<int>(todo.size()), system::thread_count(threads),
                       [&](int t, system::SystemData& data) {
                         const auto k = static_cast<std::size_t>(todo[static_cast<std::size_t>(t)]);
                         sim::PuttRequest r;
                         r.angle = launches[k][0];
                         r.speed = launches[k][1];
                         r.start = ball;
                         const sim::PuttOutcome p =
                             sim::simulate_putt(world, data.ball.get(), hole, r);
                         Imagined m;
                         m.sunk = p.sunk;
                         m.left_lane = p.end == sim::PuttEnd::kLeftLane;
                         m.rest = p.rest_position;
                         m.closest_approach = p.closest_approach;
                         out[k] = m;
                       });
  if (cache != nullptr)
    for (int k : todo)
      cache->store(key(static_cast<std::size_t>(k)), out[static_cast<std::size_t>(k)]);
  if (simulated != nullptr) *simulated = static_cast<int>(todo.size());
  return out;
}

bool line_blocked(const field::Field& field, std::array<double, 2> a, std::array<double, 2> b,
                  double clearance) {
  if (field.obstacles.empty()) return false;
  const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
  const int n = std::max(2, static_cast<int>(std::ceil(len / 0.01)));
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    const std::array<double, 2> p{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
    for (const auto& o : field.obstacles)
      if (o.distance(p) < clearance) return true;
  }
  return false;
}

double strokes_to_go(const field::Field& field, std::array<double, 2> rest, bool left_lane) {
  const auto& h = field.hole.position;
  const double d = std::hypot(h[0] - rest[0], h[1] - rest[1]);
  double v = 1.0 + 0.05 * d;
  if (line_blocked(field, rest, h, field.ball.radius)) v += 1.0;
  if (left_lane) v += 1.0;
  return v;
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
  StrokePlan best;
  best.expected_strokes = std::numeric_limits<double>::infinity();
  int simulated = 0;
  const auto consider = [&](const Block& b) {
    for (std::size_t i = 0; i < b.angles.size(); ++i)
      for (std::size_t j = 0; j < b.speeds.size(); ++j) {
        const auto [e, p] = score(field, b, i, j, error);
        // Ties: the more certain sink, then the slower putt (safer past the hole).
        if (e < best.expected_strokes - 1e-12 ||
            (std::abs(e - best.expected_strokes) <= 1e-12 && p > best.sink_probability)) {
          best.angle = wrap(b.angles[i]);
          best.speed = b.speeds[j];
          best.expected_strokes = e;
          best.sink_probability = p;
          best.bank = b.bank;
        }
      }
  };
  const double direct = std::atan2(hole[1] - ball[1], hole[0] - ball[0]);
  Block d;
  const int k = static_cast<int>(std::lround(kDirectSpan / kFineStep));
  for (int i = -k; i <= k; ++i) d.angles.push_back(direct + i * kFineStep);
  d.speeds = speed_ladder(options);
  run_block(system, ball, hole, d, options, cache, simulated);
  consider(d);
  if (best.sink_probability < options.accept_probability) {
    // All round, coarse: where do paths come near the hole?
    Block c;
    const int n = static_cast<int>(std::lround(2.0 * kPi / kCoarseStep));
    for (int i = 0; i < n; ++i) c.angles.push_back(direct + kPi * (2.0 * i / n - 1.0));
    c.speeds = speed_ladder(options, 2);
    c.bank = true;
    run_block(system, ball, hole, c, options, cache, simulated);
    // Lay-ups from the coarse grid (exact execution assumed there: its cells are too far apart
    // to smooth over) ...
    const LaunchError none{};
    for (std::size_t i = 0; i < c.angles.size(); ++i)
      for (std::size_t j = 0; j < c.speeds.size(); ++j) {
        const auto [e, p] = score(field, c, i, j, none);
        // A coarse cell stands for a lay-up only: a sink there is refined below.
        if (p == 0.0 && e < best.expected_strokes) {
          best.angle = wrap(c.angles[i]);
          best.speed = c.speeds[j];
          best.expected_strokes = e;
          best.sink_probability = 0.0;
          best.bank = true;
        }
      }
    // ... and the directions whose paths came nearest the hole, away from the direct line.
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
      run_block(system, ball, hole, r, options, cache, simulated);
      consider(r);
    }
  }
  best.imagined_putts = simulated;
  return best;
}

}  // namespace mg::game
