#pragma once
/// The physical prior the robot plans with before it has seen a putt, read from what it believes
/// of the green (docs/belief.md, "The physical prior"): Penner's rolling deceleration, the launch
/// that rolls a distance and still arrives at a speed, and the club speed that keeps a hit's
/// arrival speed when the green or the arm turn out other than surveyed. The teacher, the
/// self-teacher and the players all read it from here, so a revised belief reaches all of them.
#include <array>

#include "field/field.hpp"

namespace mg::belief {

/// [m/s^2] Penner's deceleration of a ball rolling on the level: (5/7) rho g.
double rolling_deceleration(const field::Field& field);

/// A ball launch: direction and speed.
struct LaunchGuess {
  double angle = 0.0;  ///< [rad]
  double speed = 0.0;  ///< [m/s] ball launch speed
};

/// The physics-free guess a person would start from (no putt seen yet): aim at the hole, and the
/// ball launch speed [m/s] that rolls the distance plus the climb and still has `arrival` [m/s]
/// at the hole (rolling deceleration (5/7) rho g, a launched ball keeps 5/7 of its speed once it
/// rolls). From the field's tee.
LaunchGuess prior_launch(const field::Field& field, std::array<double, 2> hole, double arrival);
/// The same from a ball at `ball` (not the tee).
LaunchGuess prior_launch(const field::Field& field, std::array<double, 2> ball,
                         std::array<double, 2> hole, double arrival);

/// [m/s] The same law backwards: the speed at the hole of a ball launched at `launch_speed` from
/// `ball` straight at `hole` (0 when it stops short).
double prior_arrival(const field::Field& field, std::array<double, 2> ball,
                     std::array<double, 2> hole, double launch_speed);

/// [m/s] An angle-only model's fixed club speed read physically: the club speed that, on the
/// green as `believed` and with an arm that reaches `club_speed_scale` of what it is commanded,
/// gives the ball the arrival speed at `hole` that `surveyed_speed` gave on the green as
/// `surveyed` (where the model learned it) with the nominal arm. A slower green or a weaker arm
/// asks for a harder hit. The launch rolls the extra energy the believed green takes over the
/// same distance and climb (Penner's law on the straight line; the launch is 1.6 times the club
/// speed, only the difference matters). `surveyed_speed` itself, bit for bit, when the two greens
/// roll alike (same rolling resistance and climb) and the scale is 1.
double equivalent_club_speed(double surveyed_speed, const field::Field& surveyed,
                             const field::Field& believed, double club_speed_scale,
                             std::array<double, 2> ball, std::array<double, 2> hole);

}  // namespace mg::belief
