#pragma once
/// An angle-only model's club speed chosen in what the robot believes (docs/belief.md, "The fixed
/// speed in a belief"): the hit's angle kept, its speed the one at which that angle sinks most
/// surely in the believed ball world (belief::choose_club_speed).
#include "field/situations.hpp"
#include "system/system.hpp"

namespace mg::system {

/// [m/s] The club speed to play a hit along `angle` [rad, world] of an angle-only model with, in
/// `system`'s belief: `equivalent_speed` (believed_fixed_speed of the model's speed) itself, bit
/// for bit, without a belief; with one, belief::choose_club_speed round it in a ball-only world of
/// the believed field, with the believed arm (club speed scale, launch bias) and the speeds the
/// arm can reach. `situation` is the believed one (believed_situation). Deterministic; about 0.1 s
/// of imagined putts.
double believed_club_speed(const System& system, const field::Situation& situation,
                           double equivalent_speed, double angle);

}  // namespace mg::system
