// Outcome equivalence of the fast full-system putt (notes/speed.md): the same putts run four
// ways and compared with the reference (RestStart::kApproach, the arm simulated to the end, a
// fresh approach: the behaviour before the speed work):
//   rest start       RestStart::kKinematicApproach (or kAtRestPose: argument at-rest-pose)
//   hand-off         the approach (from the scratch's cache), then the roll in the ball world
//   cached approach  the reference again, its approach from the cache (expected: the same bits)
// Putts per field: 50 uniform over angles [-0.3, 0.6] rad and club speeds [0.5, 2.6] m/s, 30
// around the shipped hole's sinking shot. Prints Markdown. Run:
// ./build/bench/control/speed_equivalence
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "sim_backend/full_system.hpp"

namespace {

using namespace mg;

struct Shot {
  const char* field;
  double angle, speed;
};
constexpr std::array<Shot, 4> kShots{{{"flat", 0.01, 1.6},
                                      {"multiple-hills", 0.01, 1.8},
                                      {"regular-hill", 0.01, 1.65},
                                      {"arctan", 0.03, 1.65}}};

struct Stats {
  int putts = 0, hits = 0, hit_changes = 0, sunk_ref = 0, sunk = 0, flips = 0, end_changes = 0;
  int touch_changes = 0, handed_off = 0, fallbacks = 0, refused_changes = 0;
  std::vector<double> angle, speed, club, rest, closest;
};

double max_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}
double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

void compare(Stats& s, const control::FullPuttResult& ref, const control::FullPuttResult& r,
             const std::string& label, double angle, double speed, bool print) {
  ++s.putts;
  s.hits += r.hit ? 1 : 0;
  if (r.hit != ref.hit) ++s.hit_changes;
  if (r.hit_refused != ref.hit_refused) ++s.refused_changes;
  s.sunk_ref += ref.outcome.sunk ? 1 : 0;
  s.sunk += r.outcome.sunk ? 1 : 0;
  s.handed_off += r.handed_off ? 1 : 0;
  s.fallbacks += r.handoff_fallbacks;
  if (r.club_ball_touches != ref.club_ball_touches) ++s.touch_changes;
  if (r.outcome.sunk != ref.outcome.sunk) {
    ++s.flips;
    if (print)
      std::printf(
          "flip (%s): angle %.5f speed %.4f: reference %s, now %s (launch %.5f/%.5f rad, %.5f/%.5f "
          "m/s)\n",
          label.c_str(), angle, speed, sim::to_string(ref.outcome.end).c_str(),
          sim::to_string(r.outcome.end).c_str(), ref.launch.angle, r.launch.angle, ref.launch.speed,
          r.launch.speed);
  }
  if (r.outcome.end != ref.outcome.end) ++s.end_changes;
  if (!r.hit || !ref.hit) return;
  s.angle.push_back(std::abs(r.launch.angle - ref.launch.angle));
  s.speed.push_back(std::abs(r.launch.speed - ref.launch.speed));
  s.club.push_back(std::abs(r.club.speed - ref.club.speed));
  s.rest.push_back(std::hypot(r.outcome.rest_position[0] - ref.outcome.rest_position[0],
                              r.outcome.rest_position[1] - ref.outcome.rest_position[1]));
  s.closest.push_back(std::abs(r.outcome.closest_approach - ref.outcome.closest_approach));
}

void print_row(const char* what, const char* field, const Stats& s) {
  std::printf(
      "| %s | %s | %d | %d | %d | %d | %d | %d | %d | %d | %d | %.3g / %.3g | %.3g / %.3g | %.3g / "
      "%.3g | %.3g / %.3g | %.3g |\n",
      what, field, s.putts, s.hits, s.hit_changes, s.sunk_ref, s.flips, s.end_changes,
      s.touch_changes, s.handed_off, s.fallbacks, 1e3 * max_of(s.angle), 1e3 * median_of(s.angle),
      1e3 * max_of(s.speed), 1e3 * median_of(s.speed), 1e3 * max_of(s.club),
      1e3 * median_of(s.club), 1e3 * max_of(s.rest), 1e3 * median_of(s.rest),
      1e3 * max_of(s.closest));
}

}  // namespace

int main(int argc, char** argv) {
  // The rest start under test: the kinematic approach (default) or "at-rest-pose".
  const std::string mode = argc > 1 ? argv[1] : "";
  const control::RestStart rest_start = mode == "at-rest-pose"
                                            ? control::RestStart::kAtRestPose
                                            : control::RestStart::kKinematicApproach;
  // "sensitivity": the reference against itself with the request moved by 1e-9 (rad, m/s), the
  // spread any change of bits shows (column "kinematic rest").
  const double nudge = mode == "sensitivity" ? 1e-9 : 0.0;

  const auto hitting = ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                              "/data/models/hitting-default.json");
  std::mt19937 rng(20261201);
  std::vector<std::string> rows;
  std::array<Stats, 3> total;
  const std::array<const char*, 3> names{
      rest_start == control::RestStart::kAtRestPose ? "at rest pose" : "kinematic approach",
      "hand-off", "cached approach"};
  std::array<std::array<Stats, 3>, 4> per_field;
  for (std::size_t fi = 0; fi < kShots.size(); ++fi) {
    const Shot& shot = kShots[fi];
    const sim::World world = control::make_world_with_arm(field::load_field(shot.field));
    const sim::World ball_world = control::make_ball_world(world);
    const control::ModuleModel model =
        control::make_module_model(world, hitting, control::ModuleConfig{});
    auto d = world.make_data();
    const auto hole = world.field().hole.position;
    control::PuttScratch scratch;
    control::FullPuttOptions reference, rest, handoff, both;
    reference.rest_start = control::RestStart::kApproach;
    rest.rest_start = rest_start;
    handoff.rest_start = control::RestStart::kApproach;
    handoff.ball_world = &ball_world;
    both.rest_start = control::RestStart::kApproach;  // the reference again, from the cache
    std::uniform_real_distribution<double> ua(-0.3, 0.6), uv(0.5, 2.6), na(-0.03, 0.03),
        nv(-0.2, 0.2);
    for (int i = 0; i < 80; ++i) {
      const double a = i < 50 ? ua(rng) : shot.angle + na(rng);
      const double v = i < 50 ? uv(rng) : shot.speed + nv(rng);
      const auto ref =
          control::full_system_putt(world, model, d.get(), hole, a, v, reference, nullptr);
      const auto r1 =
          nudge > 0.0
              ? control::full_system_putt(world, model, d.get(), hole, a + nudge, v + nudge,
                                          reference, &scratch)
              : control::full_system_putt(world, model, d.get(), hole, a, v, rest, &scratch);
      const auto r2 =
          control::full_system_putt(world, model, d.get(), hole, a, v, handoff, &scratch);
      const auto r3 = control::full_system_putt(world, model, d.get(), hole, a, v, both, &scratch);
      const std::array<const control::FullPuttResult*, 3> rs{&r1, &r2, &r3};
      for (std::size_t k = 0; k < 3; ++k) {
        compare(per_field[fi][k], ref, *rs[k], std::string(names[k]) + ", " + shot.field, a, v,
                true);
        compare(total[k], ref, *rs[k], "", a, v, false);
      }
    }
  }
  std::printf(
      "\n| variant | field | putts | hits | hit changes | sunk (ref) | sunk flips | end changes | "
      "touch-count changes | handed off | fallbacks | launch angle max / median [mrad] | launch "
      "speed max / median [mm/s] | club speed max / median [mm/s] | rest position max / median "
      "[mm] | closest approach max [mm] |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t k = 0; k < 3; ++k) {
    for (std::size_t fi = 0; fi < kShots.size(); ++fi)
      print_row(names[k], kShots[fi].field, per_field[fi][k]);
    print_row(names[k], "all", total[k]);
  }
  return 0;
}
