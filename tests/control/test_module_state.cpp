// Table-driven transitions of the module's state machine, without physics.
#include "control/module_state.hpp"

#include <vector>

#include <gtest/gtest.h>

namespace mg::control {
namespace {

using S = ModuleState;
using C = Command;
using R = Reason;

Observation ready_to_hit(C command = C::kHit) {
  Observation o;
  o.command = command;
  o.at_rest_pose = true;
  o.perception_fresh = true;
  o.request_valid = true;
  return o;
}

struct Row {
  const char* name;
  S from;
  Observation observation;
  S to;
  R reason;
};

std::vector<Row> table() {
  Observation none;
  Observation idle;
  idle.command = C::kIdle;
  Observation rest;
  rest.command = C::kRest;
  Observation hit_not_at_rest = ready_to_hit();
  hit_not_at_rest.at_rest_pose = false;
  Observation hit_stale = ready_to_hit();
  hit_stale.perception_fresh = false;
  Observation hit_invalid = ready_to_hit();
  hit_invalid.request_valid = false;
  Observation ball_hit;
  ball_hit.ball_hit = true;
  Observation passed;
  passed.passed_ball = true;
  Observation stationary;
  stationary.joints_stationary = true;
  Observation fault;
  fault.fault = true;
  Observation fault_with_hit = ready_to_hit();
  fault_with_hit.fault = true;
  return {
      {"idle stays idle", S::kIdle, none, S::kIdle, R::kNoChange},
      {"rest from idle", S::kIdle, rest, S::kRest, R::kUserRest},
      {"rest holds", S::kRest, ready_to_hit(C::kNone), S::kRest, R::kNoChange},
      {"hit from rest", S::kRest, ready_to_hit(), S::kHitting, R::kUserHit},
      {"hit from idle refused", S::kIdle, ready_to_hit(), S::kIdle, R::kHitRefusedNotAtRest},
      {"hit before the rest pose is reached", S::kRest, hit_not_at_rest, S::kRest,
       R::kHitRefusedNotAtRest},
      {"hit on stale perception", S::kRest, hit_stale, S::kRest, R::kHitRefusedStalePerception},
      {"hit with a bad request", S::kRest, hit_invalid, S::kRest, R::kHitRefusedInvalidRequest},
      {"second hit while hitting", S::kHitting, ready_to_hit(), S::kHitting,
       R::kHitRefusedWhileMoving},
      {"hit while braking", S::kBraking, ready_to_hit(), S::kBraking, R::kHitRefusedWhileMoving},
      {"ball hit brakes", S::kHitting, ball_hit, S::kBraking, R::kBallHit},
      {"passing the ball brakes", S::kHitting, passed, S::kBraking, R::kPassedBall},
      {"hitting continues", S::kHitting, none, S::kHitting, R::kNoChange},
      {"braking until stationary", S::kBraking, none, S::kBraking, R::kNoChange},
      {"stationary ends braking", S::kBraking, stationary, S::kIdle, R::kStationary},
      {"idle during a hit brakes first", S::kHitting, idle, S::kBraking, R::kUserIdle},
      {"idle from rest", S::kRest, idle, S::kIdle, R::kUserIdle},
      {"idle while braking waits", S::kBraking, idle, S::kBraking, R::kNoChange},
      {"rest while hitting refused", S::kHitting, rest, S::kHitting, R::kRestRefusedWhileHitting},
      {"rest while braking refused", S::kBraking, rest, S::kBraking, R::kRestRefusedWhileHitting},
      {"fault while hitting brakes", S::kHitting, fault, S::kBraking, R::kFault},
      {"fault while resting brakes", S::kRest, fault, S::kBraking, R::kFault},
      {"fault beats a hit request", S::kRest, fault_with_hit, S::kBraking, R::kFault},
      {"fault while braking keeps braking", S::kBraking, fault, S::kBraking, R::kNoChange},
      {"fault while idle stays idle", S::kIdle, fault, S::kIdle, R::kFault},
  };
}

TEST(ModuleState, TransitionTable) {
  for (const Row& row : table()) {
    const Transition t = next_state(row.from, row.observation);
    EXPECT_EQ(t.next, row.to) << row.name << ": got " << to_string(t.next);
    EXPECT_EQ(t.reason, row.reason) << row.name << ": got " << to_string(t.reason);
  }
}

// Whatever is observed, a hit only ever starts from a reached rest pose with fresh perception.
TEST(ModuleState, ExhaustiveSafetyProperties) {
  for (S from : {S::kIdle, S::kRest, S::kHitting, S::kBraking})
    for (C c : {C::kNone, C::kIdle, C::kRest, C::kHit})
      for (int bits = 0; bits < 128; ++bits) {
        Observation o;
        o.command = c;
        o.at_rest_pose = bits & 1;
        o.ball_hit = bits & 2;
        o.passed_ball = bits & 4;
        o.joints_stationary = bits & 8;
        o.perception_fresh = bits & 16;
        o.request_valid = bits & 32;
        o.fault = bits & 64;
        const Transition t = next_state(from, o);
        if (t.next == S::kHitting && from != S::kHitting) {
          EXPECT_EQ(from, S::kRest);
          EXPECT_TRUE(o.at_rest_pose && o.perception_fresh && o.request_valid && !o.fault);
        }
        if (o.fault && (from == S::kHitting || from == S::kRest)) {
          EXPECT_EQ(t.next, S::kBraking);
        }
        // Never straight from a moving hit to gravity compensation.
        if (from == S::kHitting) {
          EXPECT_NE(t.next, S::kIdle);
        }
        EXPECT_FALSE(to_string(t.reason).empty());
      }
}

}  // namespace
}  // namespace mg::control
