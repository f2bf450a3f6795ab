#pragma once
/// Bank shots for the teacher (teacher.hpp, stage 1): where an obstacle blocks the straight line,
/// fold the path at one or two borders or obstacle faces.
#include <array>
#include <vector>

#include "field/field.hpp"

namespace mg::teacher {

/// A bank shot: the launch whose path, folded at each bounce on the line the ball's centre bounces
/// on (a border's or an obstacle face's, a ball radius out) by the rebound of a rolling ball
/// (sim::rolling_rebound: it leaves the face at a flatter angle than it came), reaches the hole.
struct BankShot {
  double angle = 0.0;         ///< [rad] launch direction
  double launch_speed = 0.0;  ///< [m/s] prior: rolls every leg, loses the normal speed's share
  double path_length = 0.0;   ///< [m]
  int bounces = 1;
  /// d(lateral miss at the hole)/d(launch angle) [m/rad] at the start: each bounce mirrors the
  /// path, so the miss turns the other way once per bounce (the direct line's is -distance).
  double lateral_gain() const { return bounces % 2 == 1 ? path_length : -path_length; }
};

/// The bank shots from `ball` to `hole` off the borders and the flat faces of the obstacles: one
/// bounce (shortest path first), then two bounces (shortest first); every leg clear of the
/// obstacles by a ball radius. `arrival` [m/s] is the speed the ball should reach the hole with.
std::vector<BankShot> bank_shots(const field::Field& f, std::array<double, 2> ball,
                                 std::array<double, 2> hole, double arrival);

}  // namespace mg::teacher
