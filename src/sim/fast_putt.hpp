#pragma once
/// A fast planning path for ball-only putts: `simulate_putt`'s contract at ~10x its speed.
///
/// While the ball touches nothing but the ground (it is clear of the lane borders, every
/// obstacle and the cup), one MuJoCo step of the ball-only world is a small closed form: one
/// sphere-plane contact on the tangent plane under the ball (World::update_ground_contact), a
/// soft elliptic-cone constraint (solref/solimp/impratio of the ball-ground pair) whose optimum
/// has three cases (free, sticking, sliding on the cone) solved exactly, the rolling-resistance
/// torque of World::step, and MuJoCo's semi-implicit Euler step at the same 1 ms. `fast_putt`
/// integrates that itself and hands the state to the MuJoCo world (World::set_ball_state) for
/// every step in which the ball may touch a border, an obstacle or the cup, taking it back once
/// clear. It reproduces the MuJoCo path to rounding (positions within ~1e-12 m over a roll), so
/// no parameter is fitted. See docs/physics.md, "The planning path".
#include <array>

#include "sim/putt.hpp"

namespace mg::sim {

/// True when `fast_putt` can replace MuJoCo's ground contact in `world`: a ball-only world with
/// the tangent-plane ground (no arm, no heightfield contact), Euler integration, an elliptic
/// cone and a condim-3 ball-ground pair. Otherwise `fast_putt` runs `simulate_putt`.
bool fast_putt_applies(const World& world);

/// How `fast_putt` treats putts that are chaotic in MuJoCo itself: a ball that hops off walls at
/// speed makes a rounding-level difference grow ~10x per hop and wall hit (MuJoCo against itself
/// with the start moved by 1e-13 m: rest positions centimetres apart in 0.7-1.3 % of random
/// putts). Such a putt is replayed in MuJoCo from its start, bit for bit as simulate_putt, until
/// the ball is calm, once airtime / replay_airtime + wall hits / replay_wall_hits reaches 1.
struct FastPuttOptions {
  double replay_airtime = 1.5;  ///< [s] without ground contact; 0: never replay
  int replay_wall_hits = 15;    ///< hits of a border, an obstacle or the cup ...
  double wall_hit_speed = 1.0;  ///< [m/s] ... at more than this (planar speed)
  /// Calm: rolling for 0.1 s and slower than this [m/s] (no hop off a wall below about 1 m/s).
  double calm_speed = 1.5;
};

/// Like `simulate_putt`, for planning: its start (start_putt: request checks, InputError for bad
/// requests, holes and starts, the launch, a club's too) and its outcome rules. `d` is an `mjData`
/// of `world` (World::make_data); it is left in an unspecified state. `PuttOutcome::steps` counts
/// the MuJoCo steps taken (near borders, obstacles and the hole); `duration` and `trajectory` cover
/// the whole putt. Deterministic (same inputs, same bits), thread-safe for a shared `world` with
/// one `d` per thread, no allocation per step (a recorded trajectory is reserved up front).
PuttOutcome fast_putt(const World& world, mjData* d, std::array<double, 2> hole,
                      const PuttRequest& request, const OutcomeRules& rules = {},
                      const FastPuttOptions& options = {});

}  // namespace mg::sim
