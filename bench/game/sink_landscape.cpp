// The sink landscape round a planned stroke: which launches near it sink ('#'), stop on the lane
// ('.') or leave play ('x'), on a 41 x 41 grid 0.5 mrad and 0.2 % apart (docs/round.md: why the
// oracle launches with the arm's error).
//
// Run: ./build/bench/game/sink_landscape FIELD BALL_X BALL_Y ANGLE_ERROR SPEED_ERROR
//      (errors: the launch error the plan is made under; 0 0: exact execution)
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "game/planner.hpp"
#include "system/system.hpp"

int main(int argc, char** argv) {
  using namespace mg;
  try {
    if (argc != 6) {
      std::fprintf(stderr, "usage: sink_landscape FIELD BALL_X BALL_Y ANGLE_ERROR SPEED_ERROR\n");
      return 2;
    }
    const system::System sys(system::load_config("", argv[1]));
    const auto& f = sys.field();
    const game::PlannerOptions po;
    const std::array<double, 2> ball{std::stod(argv[2]), std::stod(argv[3])};
    const game::LaunchError error{std::stod(argv[4]), std::stod(argv[5])};
    const auto plan = game::plan_stroke(sys, ball, f.hole.position, error, po);
    std::printf("plan: angle %.5f rad, speed %.4f m/s, sink probability %.3f, bank %d\n",
                plan.angle, plan.speed, plan.sink_probability, plan.bank ? 1 : 0);
    constexpr int kHalf = 20;
    std::vector<std::array<double, 2>> launches;
    for (int i = -kHalf; i <= kHalf; ++i)
      for (int j = -kHalf; j <= kHalf; ++j)
        launches.push_back({plan.angle + i * 0.0005, plan.speed * (1.0 + j * 0.002)});
    const game::LaneRegion region(f, f.hole.position);
    int n = 0, sunk = 0;
    const auto out = game::imagine(sys, region, ball, f.hole.position, launches, po, nullptr, &n);
    std::printf("rows: angle, 0.5 mrad apart; columns: speed, 0.2 %% apart\n");
    for (std::size_t k = 0; k < out.size(); ++k) {
      sunk += out[k].sunk;
      std::putchar(out[k].sunk ? '#' : out[k].left_lane ? 'x' : '.');
      if ((k + 1) % (2 * kHalf + 1) == 0) std::putchar('\n');
    }
    std::printf("%d of %zu launches sink\n", sunk, out.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sink_landscape: %s\n", e.what());
    return 2;
  }
}
