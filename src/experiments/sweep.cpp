#include "experiments/sweep.hpp"

#include "core/csv.hpp"
#include "core/error.hpp"
#include "experiments/wire.hpp"
#include "system/distributed.hpp"

namespace mg::experiments {

std::vector<double> linspace(double lo, double hi, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(n == 1 ? lo : lo + (hi - lo) * i / (n - 1));
  return v;
}

std::vector<SweepCell> run_sweep(const system::System& system, const SweepOptions& options,
                                 const std::function<void(int, int)>& progress) {
  field::check_hole_position(system.field(), options.hole);
  system::check_real_holes(system.field(), system.plant(), {options.hole}, "sweep");
  const int na = static_cast<int>(options.angles.size()),
            ns = static_cast<int>(options.speeds.size());
  std::vector<SweepCell> cells(static_cast<std::size_t>(na * ns));
  int done = 0;
  system::distributed_for(
      system, cells, options.threads,
      [&](int i, system::SystemData& data) {
        SweepCell& c = cells[static_cast<std::size_t>(i)];
        c.angle = options.angles[static_cast<std::size_t>(i / ns)];
        c.speed = options.speeds[static_cast<std::size_t>(i % ns)];
        if (options.ball_only) {
          c.outcome = system::ball_putt(system, data, options.hole, c.angle, c.speed);
          return;
        }
        const control::FullPuttResult r =
            system::arm_putt(system, data, options.hole, c.angle, c.speed);
        c.hit = r.hit && !r.hit_refused;
        c.outcome = r.outcome;
        if (!c.hit) c.outcome.rest_position = system.field().tee;
        c.launch_angle = r.launch.angle;
        c.launch_speed = r.launch.speed;
      },
      [&](int) {
        if (progress) progress(++done, na * ns);
      });
  return cells;
}

std::string sweep_csv(const std::vector<SweepCell>& cells) {
  std::vector<std::vector<double>> rows;
  rows.reserve(cells.size());
  for (const auto& c : cells) {
    const auto& o = c.outcome;
    rows.push_back({c.angle, c.speed, o.sunk ? 1.0 : 0.0, c.hit ? o.closest_approach : 1e3,
                    o.rest_position[0], o.rest_position[1], static_cast<double>(o.end),
                    c.hit ? 1.0 : 0.0, c.launch_angle, c.launch_speed, o.duration});
  }
  return format_csv({"angle", "speed", "sunk", "closest_approach", "rest_x", "rest_y", "end", "hit",
                     "launch_angle", "launch_speed", "duration"},
                    rows);
}

}  // namespace mg::experiments
