#pragma once
/// The ball's launch as the game sees it: its error model, what the arm gave (read from the
/// ball's state when it left the club) and the arm's launch repeatability, measured.
#include <array>
#include <cstdint>
#include <vector>

#include "sim/putt.hpp"
#include "system/system.hpp"

namespace mg::game {

/// A launch's error: std of the launch angle [rad] and of the launch speed relative to its aim
/// [-]. Zero: exact execution.
struct LaunchError {
  double angle = 0.0;
  double speed = 0.0;
};

/// The launch the arm gave, in the terms of an imagined putt's request: horizontal direction
/// [rad, world], speed along the surface at the start [m/s] and the club's extras.
struct ArmLaunch {
  double angle = 0.0, speed = 0.0;
  sim::ClubLaunch club;
};

/// From the ball's state `s` when the launch was measured, the ball having lain at `start`,
/// seen on `field` (the robot's model of it).
ArmLaunch arm_launch(const field::Field& field, std::array<double, 2> start,
                     const sim::BallState& s);

/// The arm's launch repeatability: `hits` arm putts from the tee at each club speed [m/s] of
/// `club_speeds`, each with its own view of the ball (an error of `vision_noise` [m] std per
/// axis); the pooled within-speed std of the launch angle and of the relative launch speed.
LaunchError launch_precision(const system::System& system, system::SystemData& data,
                             const std::vector<double>& club_speeds, int hits, double vision_noise,
                             std::uint64_t seed);

}  // namespace mg::game
