#pragma once
/// Playing a round (docs/round.md): every hole of a course, stroke after stroke from where the
/// ball lies, by one of three players:
/// - robot: plans each stroke in its own model of the field (the field file, never the plant)
///   with the planner (game/planner.hpp), then hits with the arm (the full system, in the true
///   world): the base stands beside the ball facing the planned launch direction, and its launch
///   skill (calibrated with its own putts from the tee, counted as learning putts, and refined by
///   every stroke it plays) turns the launch into a club request.
/// - oracle: plans in the true world and plays ball-only putts there, launched with the arm's
///   measured precision (`oracle_error`): the best a planner of this search can do with this
///   arm; the baseline.
/// - exact-oracle: the oracle with exact execution (no robot launches bit-exactly; a reference).
/// - greedy: aims the arm at the hole with the speed whose imagined putt ends nearest the hole.
/// A ball out of play (it left the lane, or stopped in a part of it walled off from the hole:
/// game/lane_region.hpp) is put back at the last point of its path in play (pulled a ball radius
/// + 1 cm off borders and obstacles) with one penalty stroke; a hole ends when sunk or at
/// `max_strokes` strokes, penalties included.
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "game/course.hpp"
#include "game/lane_region.hpp"
#include "game/planner.hpp"
#include "plant/plant.hpp"
#include "system/system.hpp"

namespace mg::game {

enum class Player { kRobot, kOracle, kExactOracle, kGreedy };
std::string to_string(Player player);
/// "robot", "oracle", "exact-oracle" or "greedy"; throws InputError naming `what` otherwise.
Player parse_player(const std::string& text, const std::string& what);

/// A learned hitting model as the round plays it (`play --model`): the hit it predicts for `hole`
/// with the robot standing at `ball` facing +x (the frame it was trained in): hitting angle [rad]
/// and club speed [m/s]; nothing when the situation is not one the model knows.
struct ModelHit {
  double angle = 0.0, club_speed = 0.0;
};
using HitModel =
    std::function<std::optional<ModelHit>(std::array<double, 2> ball, std::array<double, 2> hole)>;

struct RoundOptions {
  Player player = Player::kRobot;
  std::uint64_t seed = 0;
  int calibration_putts = 10;   ///< per field: the robot's learning putts (1..50)
  double vision_noise = 0.002;  ///< [m] std per axis of the robot's view of the ball per stroke
  /// The least launch error the robot plans under, whatever its skill's fit says [rad], [-].
  double min_angle_error = 0.002;
  double min_speed_error = 0.01;
  /// The oracle's launch error (std of angle [rad] and relative speed [-]): the arm's launch
  /// repeatability under `vision_noise`, measured by bench/game/launch_precision.
  LaunchError oracle_error{0.0005, 0.007};
  /// The robot's learned models by field name: a stroke is the model's when its hit, judged in
  /// the robot's model of the field through its launch skill, sinks with at least
  /// `planner.accept_probability` or is expected to take no more strokes than the planner's.
  std::map<std::string, HitModel> models;
  /// What the robot believes of the world beyond its field files at the start (a plant's keys;
  /// empty: it believes the files; its green keys are revised, game::GreenBelief).
  plant::Plant belief;
  /// The robot revises its belief of the green from every ball it watches (calibration putts and
  /// strokes) and plans each stroke in it; false: it keeps `belief` (the rounds before revision).
  bool revise = true;
  PlannerOptions planner;
  /// What the robot's module sees in the putts the arm plays (calibration putts, strokes), e.g.
  /// the cameras (vision::camera_perception); empty: the simulator's truth. Never in the
  /// planner's imagined putts (those are the robot's model).
  system::PerceptionFactory perception;
  void validate() const;
};

struct StrokeRecord {
  std::array<double, 2> ball{0, 0};  ///< where it lay [m]
  double angle = 0.0;                ///< [rad, world] planned launch direction
  double speed = 0.0;                ///< [m/s] planned launch speed
  /// What the ball got: launch direction [rad, world] and speed [m/s] (the plan's, for the
  /// oracle; the arm's measured launch for the robot and greedy; 0, 0 for a braked hit).
  std::array<double, 2> launch{0, 0};
  std::array<double, 2> rest{0, 0};  ///< where it stopped (or left the lane) [m]
  bool sunk = false;
  bool left_lane = false;         ///< a penalty stroke follows
  double sink_probability = 0.0;  ///< the plan's
  bool bank = false;
  bool model = false;                       ///< played with a learned model (RoundOptions::models)
  std::vector<std::array<double, 2>> path;  ///< the ball's path (10 ms apart)
};

struct HoleResult {
  std::string field;
  int par = 0;
  int strokes = 0;  ///< putts + penalties
  bool sunk = false;
  std::vector<StrokeRecord> putts;
};

struct RoundResult {
  std::string course;
  Player player = Player::kRobot;
  std::vector<HoleResult> holes;
  int total_strokes = 0;
  int total_par = 0;
  int learning_putts = 0;  ///< the robot's calibration putts, over all fields
  int imagined_putts = 0;  ///< ball-only putts simulated by the planner
  /// The robot's belief of the green at the end (RoundOptions::revise): rolling resistance scale
  /// and tilt (dz/dx, dz/dy), their std, and the paths it was revised from.
  std::array<double, 3> believed_green{1.0, 0.0, 0.0};
  std::array<double, 3> believed_green_std{0.0, 0.0, 0.0};
  int belief_paths = 0;
};

/// Plays `course` on `plant` (the true world; empty: the field files). `config` is the module
/// configuration every hole's System is built from (its field replaced by the hole's). Progress:
/// `on_stroke(hole index, stroke)` after every stroke. Deterministic for a seed.
RoundResult play_round(const Course& course, const control::ModuleConfig& config,
                       const plant::Plant& plant, const RoundOptions& options,
                       ImaginedCache* cache = nullptr,
                       const std::function<void(int, const StrokeRecord&)>& on_stroke = {});

/// Where a ball that left the lane at `p` is put back (see the file comment).
std::array<double, 2> replace_ball(const field::Field& field, std::array<double, 2> p);

/// The round's rules after one stroke that did not sink: whether the ball is out of play (it left
/// the lane, or stopped outside `region`: a penalty stroke follows) and where the next stroke is
/// played from (put back at the last point of `path` in play; off a border or wall it rests
/// against; off the rim of the cup really at `cup`). `from`: where the stroke was played from
/// [m]; `rest`: where it stopped [m]; `path`: the ball's path [m]. play_round plays by it; the
/// Python Round environment too.
struct StrokeEnd {
  bool left_lane = false;            ///< a penalty stroke follows
  std::array<double, 2> next{0, 0};  ///< [m] where the ball lies for the next stroke
};
StrokeEnd end_of_stroke(const field::Field& field, const LaneRegion& region,
                        std::array<double, 2> cup, std::array<double, 2> from, sim::PuttEnd end,
                        std::array<double, 2> rest, const std::vector<std::array<double, 2>>& path);

}  // namespace mg::game
