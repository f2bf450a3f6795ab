#include "control/module_state.hpp"

namespace mg::control {

Transition next_state(ModuleState state, const Observation& o) {
  const bool moving_state = state == ModuleState::kHitting || state == ModuleState::kRest;
  if (o.fault) {
    if (moving_state) return {ModuleState::kBraking, Reason::kFault};
    // A lasting fault still ends braking once the arm stands still (then Idle holds it).
    if (state == ModuleState::kBraking)
      return o.joints_stationary ? Transition{ModuleState::kIdle, Reason::kStationary}
                                 : Transition{state, Reason::kNoChange};
    return {state, Reason::kFault};
  }
  switch (o.command) {
    case Command::kIdle:
      if (state == ModuleState::kHitting) return {ModuleState::kBraking, Reason::kUserIdle};
      if (state == ModuleState::kBraking) return {state, Reason::kNoChange};
      return {ModuleState::kIdle, Reason::kUserIdle};
    case Command::kRest:
      if (state == ModuleState::kHitting || state == ModuleState::kBraking)
        return {state, Reason::kRestRefusedWhileHitting};
      return {ModuleState::kRest, Reason::kUserRest};
    case Command::kHit:
      if (state == ModuleState::kHitting || state == ModuleState::kBraking)
        return {state, Reason::kHitRefusedWhileMoving};
      if (state != ModuleState::kRest || !o.at_rest_pose)
        return {state, Reason::kHitRefusedNotAtRest};
      if (!o.perception_fresh) return {state, Reason::kHitRefusedStalePerception};
      if (!o.ball_in_place) return {state, Reason::kHitRefusedBallNotInPlace};
      if (!o.request_valid) return {state, Reason::kHitRefusedInvalidRequest};
      return {ModuleState::kHitting, Reason::kUserHit};
    case Command::kNone:
      break;
  }
  switch (state) {
    case ModuleState::kHitting:
      if (o.ball_hit) return {ModuleState::kBraking, Reason::kBallHit};
      if (o.passed_ball) return {ModuleState::kBraking, Reason::kPassedBall};
      break;
    case ModuleState::kBraking:
      if (o.joints_stationary) return {ModuleState::kIdle, Reason::kStationary};
      break;
    case ModuleState::kIdle:
    case ModuleState::kRest:
      break;
  }
  return {state, Reason::kNoChange};
}

std::string_view to_string(ModuleState state) {
  switch (state) {
    case ModuleState::kIdle:
      return "Idle";
    case ModuleState::kRest:
      return "Rest";
    case ModuleState::kHitting:
      return "Hitting";
    case ModuleState::kBraking:
      return "Braking";
  }
  return "?";
}

std::string_view to_string(Reason reason) {
  switch (reason) {
    case Reason::kNoChange:
      return "no change";
    case Reason::kUserIdle:
      return "user asked for idle";
    case Reason::kUserRest:
      return "user asked for the rest pose";
    case Reason::kUserHit:
      return "user asked for a hit";
    case Reason::kBallHit:
      return "the ball was hit";
    case Reason::kPassedBall:
      return "the club passed the hitting point without touching the ball";
    case Reason::kStationary:
      return "all joints stationary";
    case Reason::kFault:
      return "fault";
    case Reason::kHitRefusedNotAtRest:
      return "hit refused: not at the rest pose";
    case Reason::kHitRefusedStalePerception:
      return "hit refused: no fresh perception of ball and hole";
    case Reason::kHitRefusedBallNotInPlace:
      return "hit refused: the ball is not at the hitting point";
    case Reason::kHitRefusedInvalidRequest:
      return "hit refused: no hitting model or angle/speed outside the safe envelope";
    case Reason::kHitRefusedWhileMoving:
      return "hit refused: a hit is already running";
    case Reason::kRestRefusedWhileHitting:
      return "rest refused: wait until braking ends";
  }
  return "?";
}

}  // namespace mg::control
