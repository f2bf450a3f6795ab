#pragma once
/// One putt as a user asks for it: `minigolf putt` and Python's `System.putt` call this, so both
/// check, run and report a putt the same way (the same bits and the same JSON).
#include <array>
#include <optional>

#include <nlohmann/json.hpp>

#include "sim/putt.hpp"
#include "sim_backend/full_system.hpp"
#include "system/system.hpp"

namespace mg::system {

/// [s] Spacing of a recorded ball trajectory: `minigolf putt --trajectory` and Python's
/// System.putt by default (recording changes no bit of the outcome).
inline constexpr double kTrajectoryInterval = 0.01;

/// [rad] A world direction (`aim`, a `world` angle) lies in [-this, this]: pi and a little, the
/// bound of a ball-only launch angle (sim::PuttRequest).
inline constexpr double kMaxWorldAngle = 3.15;

/// What a user asks for.
struct PuttSpec {
  /// [rad] With the arm: the hitting angle in the base's frame; ball only: the launch angle,
  /// counter-clockwise from +x.
  double angle = 0.0;
  double speed = 0.0;  ///< [m/s] with the arm: the club speed; ball only: the launch speed
  std::optional<std::array<double, 2>> hole;  ///< [m] where the robot sees the hole (the field's)
  std::optional<std::array<double, 2>> ball;  ///< [m] where the ball lies (the tee)
  /// [rad, world] With the arm: the direction the base's hitting frame faces (default: from the
  /// ball to the hole with `ball`, else 0). Not for ball-only putts.
  std::optional<double> aim;
  /// With the arm: `angle` is a world direction and the base stands by the stance rule for hits
  /// (system::hit_pose: facing +x when the fixed arm can make the hit, else turned to it), as
  /// learned models' hits are played. Not with `aim` or ball_only.
  bool world = false;
  bool ball_only = false;        ///< launch the ball directly (no arm)
  double max_duration = 30.0;    ///< [s] give up after this simulated time
  double record_interval = 0.0;  ///< [s] ball trajectory spacing (0: none); with the arm from
                                 ///< the club's first contact
  /// Not owned. With the arm: what the module perceives instead of the simulator's truth
  /// (control::FullPuttOptions::perception_source; the cameras). nullptr: the truth.
  perception::PerceptionSource* perception_source = nullptr;
};

/// What happened.
struct PuttReport {
  bool ball_only = true;
  std::array<double, 2> hole{0, 0};  ///< [m] as seen (the spec's or the field's)
  std::array<double, 2> ball{0, 0};  ///< [m] where the ball lay
  double aim = 0.0;                  ///< [rad, world] the base's facing (arm putts)
  sim::PuttOutcome outcome;
  control::AngleSpeed club, launch;  ///< arm putts: club before contact, ball launch
  control::CoreTiming timing;        ///< arm putts: wall-clock time of the core updates
};

/// Checks `spec` (InputError naming the quantity: a ball off the lane, `aim` without the arm,
/// `world` with `aim` or ball only, a world direction beyond kMaxWorldAngle, a request outside
/// the safe envelope, a hole off the lane), then plays the putt with `data`:
/// ball only, `sim::simulate_putt` in the ball world with the hole where the plant puts it;
/// with the arm, `arm_putt` with the base beside the ball (putt_stance). InputError if the module
/// refuses the hit, NumericalError if the club does not reach the ball. Deterministic.
PuttReport putt(const System& system, SystemData& data, const PuttSpec& spec);

/// The JSON object of `minigolf putt --json`: field, hole, ball, angle, speed, sunk, end,
/// rest_position, closest_approach, duration, steps, plant; with the arm also aim, club, launch
/// and timing.
nlohmann::json putt_json(const System& system, const PuttSpec& spec, const PuttReport& report);

}  // namespace mg::system
