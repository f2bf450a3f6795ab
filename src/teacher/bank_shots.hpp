#pragma once
/// Bank shots for the teacher (teacher.hpp, stage 1): where an obstacle blocks the straight line,
/// aim at the hole's mirror image across a border.
#include <array>
#include <vector>

#include "field/field.hpp"

namespace mg::teacher {

/// A bank shot off one border: the launch that aims at the hole's mirror image across the line
/// the ball's centre bounces on (the border's face a ball radius into the lane).
struct BankShot {
  double angle = 0.0;         ///< [rad] launch direction
  double launch_speed = 0.0;  ///< [m/s] prior: rolls both legs, loses the normal speed's share
  double path_length = 0.0;   ///< [m]
};

/// The bank shots from `ball` off the four borders whose two legs are clear of obstacles,
/// shortest first; `arrival` [m/s] is the speed the ball should reach the hole with.
std::vector<BankShot> bank_shots(const field::Field& f, std::array<double, 2> ball,
                                 std::array<double, 2> hole, double arrival);

}  // namespace mg::teacher
