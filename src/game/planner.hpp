#pragma once
/// Choosing a stroke (docs/round.md "How a stroke is played"): a search over ball launches with
/// imagined ball-only putts in a world (the robot's own model of the field, or the true one for the
/// oracle planner), scored by the expected strokes to finish the hole under a launch error.
///
/// 1. Direct: launch angles around the line to the hole (+-kDirectSpan, kFineStep apart) at a
///    geometric ladder of launch speeds.
/// 2. If no direct launch sinks with probability >= accept_probability: every direction around
///    the ball (kCoarseStep apart, every other speed), then the kRefineRegions directions whose
///    paths came nearest the hole, refined at kFineStep (bank shots off borders and walls).
/// 3. Score of a launch: E = 1 + sum over its neighbours in the launch grid within 2 sigma,
///    weighted by the launch error (a Gaussian in angle and in relative speed), of
///    (1 - sunk) V(rest), with V the strokes-to-go heuristic below.
/// 4. The kCandidates best cells of steps 1-2 (apart from each other) are judged again on a fine
///    grid round each, spaced at half the launch error: a coarse cell that sank may sit on a
///    window's edge. The smallest E there wins (a lay-up when nothing sinks surely).
/// V(p) = 1 + [the straight line from p to the hole is blocked by an obstacle] + 0.05 per metre
/// to the hole; a ball that left the lane adds its penalty stroke.
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <tuple>
#include <vector>

#include "field/field.hpp"
#include "game/lane_region.hpp"
#include "game/launch.hpp"
#include "sim/putt.hpp"
#include "system/system.hpp"

namespace mg::game {

/// What the search needs of an imagined putt.
struct Imagined {
  bool sunk = false;
  bool left_lane = false;  ///< left the lane or stopped out of play (game/lane_region.hpp)
  std::array<double, 2> rest{0, 0};  ///< [m]
  double closest_approach = 0.0;     ///< [m]
};

struct PlannerOptions {
  double speed_min = 0.35;  ///< [m/s] launch speeds searched
  double speed_max = 4.2;
  int speeds = 22;                  ///< geometric ladder
  double accept_probability = 0.9;  ///< a direct sink this sure ends the search
  /// How the ball leaves the club at a launch speed [m/s] (the robot's launch skill); empty: a
  /// plain launch (the oracle's exact ball-only putts).
  std::function<sim::ClubLaunch(double)> club_launch;
  int threads = 0;  ///< 0: all cores
  void validate() const;
};

inline constexpr double kFineStep = 0.004;   ///< [rad]
inline constexpr double kDirectSpan = 0.14;  ///< [rad]
inline constexpr double kCoarseStep = 0.02;  ///< [rad]
inline constexpr int kRefineRegions = 6;
inline constexpr double kRefineSpan = 0.03;        ///< [rad]
inline constexpr int kCandidates = 4;              ///< coarse cells judged again on a fine grid
inline constexpr int kRefineHalfCells = 7;         ///< fine grid: 15 x 15 cells round a candidate
inline constexpr double kRefineAngleMin = 0.0005;  ///< [rad] least fine-grid spacing
inline constexpr double kRefineSpeedMin = 0.002;   ///< [-] least relative fine-grid spacing

struct StrokePlan {
  double angle = 0.0;  ///< [rad, world] launch direction
  double speed = 0.0;  ///< [m/s] launch speed
  double sink_probability = 0.0;
  double expected_strokes = 0.0;  ///< to finish the hole, this stroke included
  bool bank = false;              ///< found by the all-round search (not near the direct line)
  int imagined_putts = 0;         ///< putts simulated for this plan (cache hits excluded)
};

/// Memo of imagined putts by (world, ball, angle, speed, hole, club launch) bits: a deterministic
/// function, so the same stroke situation (the tee of every seed, the oracle and a robot sharing
/// a world) is searched once. Thread-safe.
class ImaginedCache {
 public:
  using Key = std::array<double, 14>;
  bool find(const Key& key, Imagined& out) const;
  void store(const Key& key, const Imagined& value);

 private:
  mutable std::mutex mutex_;
  std::map<Key, Imagined> map_;
};

/// Ball-only putts in `system`'s ball world from `ball`, simulated (the fast planning path) in
/// parallel; results by index (the same bits for any thread count). `region`: the lane's part in
/// play for `hole`.
std::vector<Imagined> imagine(const system::System& system, const LaneRegion& region,
                              std::array<double, 2> ball, std::array<double, 2> hole,
                              const std::vector<std::array<double, 2>>& launches,
                              const PlannerOptions& options, ImaginedCache* cache, int* simulated);

/// Strokes-to-go heuristic V after a ball that did not sink stops at `rest` (see file comment).
double strokes_to_go(const field::Field& field, std::array<double, 2> rest, bool left_lane);

using field::line_blocked;

/// One launch judged as plan_stroke judges its candidates (its neighbours on a fine grid at the
/// scale of `error`): expected strokes to finish the hole and sink probability.
struct LaunchJudgement {
  double expected_strokes = 0.0;
  double sink_probability = 0.0;
  int imagined_putts = 0;
};
LaunchJudgement judge_launch(const system::System& system, std::array<double, 2> ball,
                             std::array<double, 2> hole, double angle, double speed,
                             const LaunchError& error, const PlannerOptions& options,
                             ImaginedCache* cache = nullptr);

/// The best stroke from `ball` to `hole` in `system`'s ball world under `error`.
StrokePlan plan_stroke(const system::System& system, std::array<double, 2> ball,
                       std::array<double, 2> hole, const LaunchError& error,
                       const PlannerOptions& options, ImaginedCache* cache = nullptr);

}  // namespace mg::game
