#pragma once
/// An angle-only model's club speed chosen anew in a revised belief (docs/belief.md, "The fixed
/// speed in a belief"). The arrival-equivalent speed (equivalent_club_speed) keeps a chosen
/// speed's difficulty: the survey's fixed speed may sit at the edge of its sinking window, and
/// keeping its arrival speed keeps the edge. Here the robot imagines, in the ball world it
/// believes in, hits along the model's angle at club speeds round the equivalent one, and takes
/// the speed at which that angle sinks most surely under its launch errors.
#include <array>

#include "sim/world.hpp"

namespace mg::belief {

/// Measured launch speed / club speed of the nominal arm (1.54-1.67, docs/control.md).
inline constexpr double kNominalLaunchPerClub = 1.6;
/// How the robot's own arm model launches the ball, measured on its putts (club speeds 1.5-2.1
/// m/s, hitting angles -0.1..0.1 rad; tests/system/test_believed_speed.cpp keeps it true): the
/// launch speed per commanded club speed, and the launch direction minus the hitting angle.
inline constexpr double kArmLaunchPerCommand = 1.645;
inline constexpr double kArmLaunchAngleOffset = -0.0063;  ///< [rad]

struct SpeedChoiceOptions {
  int speed_steps = 10;        ///< club speeds equivalent * (1 + k step), k in -steps..steps
  double speed_step = 0.02;    ///< [-] relative
  int angle_cells = 5;         ///< launch angles angle + i angle_step, i in -cells..cells
  double angle_step = 0.004;   ///< [rad]
  double angle_sigma = 0.008;  ///< [rad] the error of the model's angle the choice allows for
  double speed_sigma = 0.03;   ///< [-] the relative error of the launch speed
  double launch_per_club = kNominalLaunchPerClub;  ///< ball launch speed per club speed
  double launch_angle_bias = 0.0;  ///< [rad] added to the hit's angle for the ball's launch
  double speed_min = 0.0;          ///< [m/s] club speeds outside [min, max] are not chosen
  double speed_max = 1e9;
  void validate() const;  ///< throws InputError naming the bad option
};

struct SpeedChoice {
  double club_speed = 0.0;  ///< [m/s]
  /// The chosen speed's score: the sink probability under the Gaussian launch errors (0..1).
  double score = 0.0;
  int imagined_putts = 0;
};

/// The club speed at which a hit along `angle` [rad, world] from `ball` sinks in `hole` most
/// surely in `world` (a ball-only world of the believed field): imagined putts (sim::fast_putt,
/// plain launches of launch_per_club times the club speed) on the grid of angles and speeds
/// round (angle, equivalent_speed); each speed scored by the sink indicator weighted by Gaussians
/// in the angle (angle_sigma) and the relative speed (speed_sigma), cells off the grid counting
/// as misses. The highest score wins, ties to the speed nearest `equivalent_speed`; when no
/// imagined putt sinks, `equivalent_speed` (clamped to the speed range). Deterministic; one
/// mjData of its own.
SpeedChoice choose_club_speed(const sim::World& world, std::array<double, 2> ball,
                              std::array<double, 2> hole, double angle, double equivalent_speed,
                              const SpeedChoiceOptions& options = {});

}  // namespace mg::belief
