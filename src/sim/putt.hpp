#pragma once
/// A ball-only putt: launch the ball from the tee and simulate until the outcome is decided.
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "sim/world.hpp"

namespace mg::sim {

/// The ball as a club leaves it, beyond a plain launch: the arm's putts hop and spin
/// (game/skill.hpp learns this from its own putts). All zero: a plain launch (on the ground,
/// sliding, no spin). Launch frame: x along the launch angle, y to its left, z up.
struct ClubLaunch {
  double advance = 0.0;                 ///< [m] the ball starts this far along x
  double lift = 0.0;                    ///< [m] its centre this far above its resting height
  double vertical_speed = 0.0;          ///< [m/s] added to the launch velocity
  std::array<double, 3> spin{0, 0, 0};  ///< [rad/s] angular velocity, launch frame
  bool plain() const {
    return advance == 0.0 && lift == 0.0 && vertical_speed == 0.0 && spin[0] == 0.0 &&
           spin[1] == 0.0 && spin[2] == 0.0;
  }
};

/// What to simulate.
struct PuttRequest {
  double angle = 0.0;  ///< [rad] counter-clockwise from +x (the default hitting direction)
  double speed = 1.0;  ///< [m/s] launch speed along the surface, no spin (the ball slides first)
  /// Where the ball starts (default: the field's tee) [m].
  std::optional<std::array<double, 2>> start;
  /// Start already rolling (spin matched to the speed) instead of sliding without spin.
  bool rolling_start = false;
  /// The club's launch (overrides rolling_start when not plain).
  ClubLaunch club;
  double max_duration = 30.0;    ///< [s] give up after this much simulated time
  double record_interval = 0.0;  ///< [s] trajectory sample spacing; 0 = no trajectory
  void validate() const;
};

/// One trajectory sample, world frame.
struct BallSample {
  double t;           ///< [s]
  double x, y, z;     ///< ball centre [m]
  double vx, vy, vz;  ///< [m/s]
};

enum class PuttEnd { kSunk, kAtRest, kTimeOut, kLeftLane };

/// The result of a putt.
struct PuttOutcome {
  bool sunk = false;
  PuttEnd end = PuttEnd::kTimeOut;
  std::array<double, 2> rest_position{0, 0};  ///< ball (x, y) when the run ended [m]
  double closest_approach = 0.0;  ///< min horizontal distance ball centre - hole centre [m]
  /// How the ball met the hole: when it first crossed the rim, its horizontal speed then [m/s] and
  /// the signed offset of its line from the hole centre (`lateral` > 0: the centre lay to the
  /// left of its direction of travel) [m], `along` = 0. A ball that never reached the rim: the same
  /// at its closest approach (direction: the last one while it moved faster than 2 cm/s), with
  /// `along` > 0 [m] when the hole was still ahead (it stopped short). What a teacher corrects the
  /// aim and the speed by.
  double approach_speed = 0.0;
  double approach_lateral = 0.0;
  double approach_along = 0.0;
  double duration = 0.0;  ///< simulated time until the outcome was decided [s]
  int steps = 0;          ///< physics steps taken
  std::vector<BallSample> trajectory;
};

std::string to_string(PuttEnd end);

/// Decides when a putt is over (shared by the ball-only path and, later, the arm).
struct OutcomeRules {
  double rest_speed = 0.005;  ///< [m/s] below this the ball counts as still
  double rest_time = 0.1;     ///< [s] ... for this long
  /// A ball that has dropped into the cup (centre below its rolling height by half the depth,
  /// capped at half its radius) and stays there this long is holed, even if it keeps rolling
  /// around a shallow cup. [s]
  double settle_time = 0.3;
};

/// Checks `request`, resets `d`, sets the hole and launches the ball (simulate_putt's start, also
/// fast_putt's replay). Throws `InputError` for a bad request, hole or start.
void start_putt(const World& world, mjData* d, std::array<double, 2> hole,
                const PuttRequest& request);

/// Resets `d`, sets the hole, launches the ball from the tee and simulates. Deterministic: the
/// same world, hole and request give the same bits.
PuttOutcome simulate_putt(const World& world, mjData* d, std::array<double, 2> hole,
                          const PuttRequest& request, const OutcomeRules& rules = {});

/// Watches a running simulation and decides sunk / at rest / left the lane. Used by
/// `simulate_putt` and by anything else that moves the ball (the arm).
class OutcomeTracker {
 public:
  OutcomeTracker(const World& world, const mjData* d, const OutcomeRules& rules);
  /// The same without an `mjData` (fast_putt): the hole at `hole` [m] and the ball's first state,
  /// `time` [s], centre `position` [m] and `velocity` [m/s] (3 each, world frame).
  OutcomeTracker(const World& world, std::array<double, 2> hole, const OutcomeRules& rules,
                 double time, const double* position, const double* velocity);
  /// Starts over from the ball's state in `d` (same hole and rules): the tracker is then the one
  /// the first constructor would make from `d`, without any field evaluation (for a real-time
  /// thread: copy a tracker made earlier for this hole, `prepare` it, `restart` it at the hit).
  void restart(const mjData* d);
  /// Evaluates now what a tracker may need of the field later (the lowest ground), so `update`
  /// and `restart` never evaluate the field.
  void prepare() { (void)lowest_z(); }
  /// Call after every physics step; returns true once the outcome is decided.
  bool update(const mjData* d);
  /// The same from the ball's state (world frame, as above).
  bool update(double time, const double* position, const double* velocity);
  PuttOutcome outcome() const { return outcome_; }

 private:
  /// Lowest ground on a 21 x 21 grid over the lane [m]; computed at first need (only a ball
  /// falling below some ground asks), so trackers stay cheap to make.
  double lowest_z();

  const World* world_;
  OutcomeRules rules_;
  std::array<double, 2> hole_;
  double hole_radius_;
  double rim_z_;
  double still_since_ = -1.0;
  double inside_since_ = -1.0;
  double corner_z_;  ///< ground at the grid's first point, an upper bound of lowest_z_
  double lowest_z_ = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not computed yet
  double heading_x_ = 1.0, heading_y_ = 0.0;                    ///< last direction of travel (unit)
  bool reached_rim_ = false;
  PuttOutcome outcome_;
};

}  // namespace mg::sim
