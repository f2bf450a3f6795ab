#pragma once
/// The minigolf module's states and their pure transition function (thesis 4.2.1).
///
/// Idle: gravity compensation, the arm stays where it is left. Rest: move to the rest pose with
/// the club face perpendicular to the hitting direction. Hitting: follow the hitting DS. Braking:
/// lift the club slightly and brake every joint; Idle once stationary.
///
/// `next_state` is a pure function of (state, observation): no clock, no I/O, no allocation, so
/// the 500 Hz core update can call it and tests can drive it from a table without physics.
#include <string_view>

namespace mg::control {

enum class ModuleState { kIdle, kRest, kHitting, kBraking };

/// What the user asked for since the last tick.
enum class Command { kNone, kIdle, kRest, kHit };

/// Everything the transition depends on, measured by the module for this tick.
struct Observation {
  Command command = Command::kNone;
  bool at_rest_pose = false;       ///< club at the rest pose, face aligned, nearly still
  bool ball_hit = false;           ///< the club touched the ball (or the ball started moving)
  bool passed_ball = false;        ///< the hitting DS reached the hitting point without contact
  bool joints_stationary = false;  ///< every joint speed under the stationary threshold
  bool perception_fresh = false;   ///< ball and hole perceived recently enough to act on
  bool ball_in_place = true;       ///< the perceived ball lies at the hitting point
  bool request_valid = false;      ///< hitting model loaded, angle/speed inside the safe envelope
  bool fault = false;              ///< NaN, lost ball, limit violation, overrun streak
};

/// Why the state is what it is after a tick (printed by the console, recorded).
enum class Reason {
  kNoChange,
  kUserIdle,
  kUserRest,
  kUserHit,
  kBallHit,
  kPassedBall,
  kStationary,
  kFault,
  kHitRefusedNotAtRest,
  kHitRefusedStalePerception,
  kHitRefusedBallNotInPlace,
  kHitRefusedInvalidRequest,
  kHitRefusedWhileMoving,
  kRestRefusedWhileHitting,
};

struct Transition {
  ModuleState next;
  Reason reason;
};

/// The transition function. Safety first: a fault or an idle request during a hit brakes the
/// arm (never a jump to gravity compensation at speed); a hit starts only from a reached rest
/// pose with fresh perception and a valid request.
Transition next_state(ModuleState state, const Observation& observation);

std::string_view to_string(ModuleState state);
std::string_view to_string(Reason reason);

}  // namespace mg::control
