#pragma once
/// A ball-only putt: launch the ball from the tee and simulate until the outcome is decided.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "sim/world.hpp"

namespace mg::sim {

/// What to simulate.
struct PuttRequest {
  double angle = 0.0;  ///< [rad] counter-clockwise from +x (the default hitting direction)
  double speed = 1.0;  ///< [m/s] launch speed along the surface, no spin (the ball slides first)
  /// Where the ball starts (default: the field's tee) [m].
  std::optional<std::array<double, 2>> start;
  /// Start already rolling (spin matched to the speed) instead of sliding without spin.
  bool rolling_start = false;
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

/// Resets `d`, sets the hole, launches the ball from the tee and simulates. Deterministic: the
/// same world, hole and request give the same bits.
PuttOutcome simulate_putt(const World& world, mjData* d, std::array<double, 2> hole,
                          const PuttRequest& request, const OutcomeRules& rules = {});

/// Watches a running simulation and decides sunk / at rest / left the lane. Used by
/// `simulate_putt` and by anything else that moves the ball (the arm).
class OutcomeTracker {
 public:
  OutcomeTracker(const World& world, const mjData* d, const OutcomeRules& rules);
  /// Call after every physics step; returns true once the outcome is decided.
  bool update(const mjData* d);
  PuttOutcome outcome() const { return outcome_; }

 private:
  const World* world_;
  OutcomeRules rules_;
  std::array<double, 2> hole_;
  double hole_radius_;
  double rim_z_;
  double still_since_ = -1.0;
  double inside_since_ = -1.0;
  double lowest_z_;
  double heading_x_ = 1.0, heading_y_ = 0.0;  ///< last direction of travel (unit)
  bool reached_rim_ = false;
  PuttOutcome outcome_;
};

}  // namespace mg::sim
