// A round's CPU time by player, and ball-only putts per second on a lane with its obstacles and
// on the same lane without them (the cost of colliding walls and blocks).
//
// Run: ./build/bench/game/bench_round --benchmark_min_time=2   (CPU time: one thread)
#include <array>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/rng.hpp"
#include "game/round.hpp"
#include "sim/putt.hpp"
#include "system/system.hpp"

namespace {

using namespace mg;

void BM_Round(benchmark::State& state, const std::string& course_name, game::Player player) {
  const game::Course course = game::load_course(course_name);
  const auto config = system::load_config("", "");
  game::RoundOptions o;
  o.player = player;
  o.planner.threads = 1;
  int strokes = 0, imagined = 0, rounds = 0;
  for (auto _ : state) {
    o.seed = static_cast<std::uint64_t>(rounds++);
    const game::RoundResult r = game::play_round(course, config, {}, o);  // no cache: cold
    strokes += r.total_strokes;
    imagined += r.imagined_putts;
  }
  state.counters["strokes_per_round"] = static_cast<double>(strokes) / rounds;
  state.counters["imagined_putts_per_round"] = static_cast<double>(imagined) / rounds;
}

/// 64 putts from the tee in every direction at 1-3.5 m/s, the same set on every world.
std::vector<sim::PuttRequest> launches() {
  std::vector<sim::PuttRequest> v;
  Rng rng(7);
  std::uniform_real_distribution<double> angle(-3.14, 3.14), speed(1.0, 3.5);
  for (int k = 0; k < 64; ++k) {
    sim::PuttRequest q;
    q.angle = angle(rng);
    q.speed = speed(rng);
    v.push_back(q);
  }
  return v;
}

void BM_BallPutts(benchmark::State& state, const std::string& field_name, bool obstacles) {
  field::Field f = field::load_field(field_name);
  if (!obstacles) f.obstacles.clear();
  const sim::World world(f);
  auto d = world.make_data();
  const auto requests = launches();
  long putts = 0;
  for (auto _ : state)
    for (const auto& q : requests) {
      benchmark::DoNotOptimize(
          sim::simulate_putt(world, d.get(), f.hole.position, q).closest_approach);
      ++putts;
    }
  state.counters["putts_per_s"] =
      benchmark::Counter(static_cast<double>(putts), benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(BM_Round, open_lane_oracle, "open-lane", game::Player::kOracle)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Round, open_lane_robot, "open-lane", game::Player::kRobot)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Round, obstacles_robot, "obstacles", game::Player::kRobot)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_BallPutts, bank_shot_with_obstacles, "bank-shot", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BallPutts, bank_shot_without, "bank-shot", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BallPutts, l_shape_with_obstacles, "l-shape", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BallPutts, l_shape_without, "l-shape", false)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
