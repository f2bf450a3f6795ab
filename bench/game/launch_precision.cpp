// The arm's launch repeatability: how far apart the launches of the same club request fall when
// the robot sees the ball with its vision error (2 mm std per axis, game::RoundOptions). The
// oracle of a round launches with this error (RoundOptions::oracle_error, docs/round.md).
//
// Run: ./build/bench/game/launch_precision [field] [hits per club speed]
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "game/launch.hpp"
#include "game/round.hpp"
#include "system/system.hpp"

int main(int argc, char** argv) {
  using namespace mg;
  try {
    const std::string field = argc > 1 ? argv[1] : "flat";
    const int hits = argc > 2 ? std::atoi(argv[2]) : 20;
    system::System sys(system::load_config("", field));
    system::SystemData data(sys);
    const auto& mc = sys.module().config();
    const double lo = mc.speed_min, hi = std::min(mc.speed_max, mc.arm_speed_cap);
    const game::RoundOptions defaults;
    std::printf("%s, vision error %.1f mm, %d hits per club speed\n", field.c_str(),
                1e3 * defaults.vision_noise, hits);
    std::printf("| club speed [m/s] | angle std [mrad] | speed std [%%] |\n|---|---|---|\n");
    std::vector<double> all;
    for (int k = 0; k < 5; ++k) {
      const double club = lo + (hi - lo) * (0.1 + 0.2 * k);
      all.push_back(club);
      const auto e = game::launch_precision(sys, data, {club}, hits, defaults.vision_noise, 7 + k);
      std::printf("| %.2f | %.2f | %.2f |\n", club, 1e3 * e.angle, 100 * e.speed);
    }
    const auto e = game::launch_precision(sys, data, all, hits, defaults.vision_noise, 7);
    std::printf("| pooled | %.2f | %.2f |\n", 1e3 * e.angle, 100 * e.speed);
    std::printf("oracle_error: %.2f mrad, %.2f %%\n", 1e3 * defaults.oracle_error.angle,
                100 * defaults.oracle_error.speed);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "launch_precision: %s\n", e.what());
    return 2;
  }
}
