#pragma once
/// What the learners read of a putt the arm played: the ball's path and its launch as the robot
/// perceived them. With the simulator's truth that is the recorded trajectory and the measured
/// launch, untouched; with a perception that watches the whole roll (the cameras of
/// vision/camera_perception.hpp), the path it saw, time-stamped at its own rate, and the launch
/// read from that path. The self-teacher, the launch skill, the belief's fits and revisions
/// call perceive_putt and never ask which perception it was.
#include <array>
#include <vector>

#include "sim/putt.hpp"
#include "sim_backend/full_system.hpp"
#include "system/system.hpp"

namespace mg::system {

/// A perception source (System::perception_factory) that also watches the ball's roll after the
/// hand-off, where the module no longer looks.
class PathObserver {
 public:
  virtual ~PathObserver() = default;
  /// The ball path of the last putt this source perceived, `result` that putt's result (played
  /// on `system`): samples from the first contact on, `t` counted from it as in the recorded
  /// trajectory, only where the ball was seen (a lost frame gives no sample). The roll after the
  /// hand-off is rendered from `result.outcome.trajectory`, so the putt must have recorded one.
  /// A putt it did not watch (played with another perception source) gives an empty path.
  virtual std::vector<sim::BallSample> observe_path(const System& system,
                                                    const control::FullPuttResult& result) = 0;
};

/// True when `system`'s putts are seen by a perception of its own (a PerceptionFactory): the
/// paths the learners read are then what it saw, with its own errors, and the plant's Gaussian
/// vision noise on paths is not added on top of them.
bool paths_seen_by_perception(const System& system);

/// [s] The launch is read from the path's first samples up to this long after the contact.
inline constexpr double kLaunchWindow = 0.3;

/// The ball's horizontal position [m] and velocity [m/s] at `at` [s] read from `path` (samples
/// in time order): least-squares quadratics in time over its samples in [0, window], i.e. the
/// plain sliding launch that continues into the roll seen (the ball hops off the club and lands
/// within 0.1 s, where a camera does not tell it from the club: the hop is folded into the
/// launch). Not seen (`seen` false) with fewer than 3 samples there or none in its first 60 %.
struct SeenLaunch {
  bool seen = false;
  std::array<double, 2> position{0.0, 0.0};
  std::array<double, 2> velocity{0.0, 0.0};
};
SeenLaunch launch_from_path(const std::vector<sim::BallSample>& path, double at,
                            double window = kLaunchWindow);

/// [s] How much of the roll after the launch `fit_launch_to_roll` follows.
inline constexpr double kLaunchFitHorizon = 2.0;

/// The plain sliding launch from `seen`'s position whose roll in `believed` (a ball-only world of
/// the field the robot believes in) best follows `path` over [at, at + horizon]: its speed scale
/// and direction fitted by damped Gauss-Newton (finite differences of sim::fast_putt) to the
/// seen positions. The kinematic launch (launch_from_path) folds the hop off the club into a
/// slide 3-4 % too fast: imagined from it, a roll ended 7-49 cm from where the real one did. What
/// the planner imagines from the launch skill is then the roll the cameras saw. The path is read
/// up to its first sample within 3 cm (+ the ball's radius) of the lane's bounds or an obstacle.
/// `seen` itself when it is not seen or fewer than 5 samples remain. Deterministic.
SeenLaunch fit_launch_to_roll(const sim::World& believed, const std::vector<sim::BallSample>& path,
                              double at, const SeenLaunch& seen,
                              double horizon = kLaunchFitHorizon);

/// Makes `result` (of arm_putt or arm_hit on `system` with `data`, the last putt played with
/// `data`) what the robot perceived of it. Without a PathObserver (the simulator's truth):
/// unchanged, bit for bit. With one: `outcome.trajectory` is the path it saw; `launch` and
/// `launch_state` are read from that path (position and velocity at the launch time; the ball on
/// the believed surface, moving along it, no spin: what a camera cannot see is not made up), NaN
/// when the cameras did not see the launch. The verdict (sunk, rest position, closest approach)
/// stays the referee's. Call on the thread that played the putt, before the next one.
void perceive_putt(const System& system, SystemData& data, control::FullPuttResult& result);

}  // namespace mg::system
