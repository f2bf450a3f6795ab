#pragma once
/// The outcome of every (angle, speed) cell of a grid, on the full system or the ball alone: the
/// teacher's and the reader's view of a sinking window (`minigolf sweep`).
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "system/system.hpp"

namespace mg::experiments {

/// `n` values from `lo` to `hi` inclusive ("A0:A1:N" on the command line).
std::vector<double> linspace(double lo, double hi, int n);

struct SweepOptions {
  std::array<double, 2> hole{0, 0};  ///< [m]
  std::vector<double> angles;        ///< [rad] (club hitting angle, or ball launch angle)
  std::vector<double> speeds;        ///< [m/s] (club speed, or ball launch speed)
  bool ball_only = false;
  int threads = 0;  ///< 0: all cores
};

struct SweepCell {
  double angle = 0.0, speed = 0.0;
  bool hit = true;  ///< full system: the club struck the ball (false: refused or no contact)
  sim::PuttOutcome outcome;
  double launch_angle = 0.0, launch_speed = 0.0;  ///< full system: the measured launch
};

/// Angle-major cells. Same bits for any thread count. `progress(done, total)` (optional).
std::vector<SweepCell> run_sweep(const system::System& system, const SweepOptions& options,
                                 const std::function<void(int, int)>& progress = {});

/// CSV: angle,speed,sunk,closest_approach,rest_x,rest_y,end,hit,launch_angle,launch_speed,duration
/// (end: 0 sunk, 1 at rest, 2 time out, 3 left the lane; launch columns 0 for ball-only putts).
std::string sweep_csv(const std::vector<SweepCell>& cells);

}  // namespace mg::experiments
