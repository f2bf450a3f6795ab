#pragma once
/// The robot's launch skill on a field (docs/round.md): what its arm does to the ball, learned
/// from its own putts. Launch speed = a line in the club speed (least squares) plus a GP of the
/// line's residual (the putter's ratio of launch to club speed bends over the envelope by about
/// 6 %: 1.57 at 0.6 m/s, 1.67 at 2 m/s, 1.64 at 2.4 m/s); launch angle = hitting angle + an offset
/// that is a GP in the club speed too (-5.8 to -7.0 mrad over the envelope). The GPs' noise
/// hyperparameters are the execution error the planner plans under. And how the ball leaves the
/// club (it hops: 8 mm up, 0.35 m/s upwards at 2.7 m/s; sim::ClubLaunch), per unit launch speed,
/// interpolated between the putts seen: the planner's imagined putts start that way.
#include <vector>

#include "sim/putt.hpp"
#include "stats/gpr.hpp"

namespace mg::game {

class LaunchSkill {
 public:
  /// One putt: club speed [m/s] and hitting angle [rad] asked of the module, and the launch the
  /// ball got (angle in the robot's frame [rad], speed [m/s]). Refits.
  void add(double club_speed, double hitting_angle, double launch_angle, double launch_speed,
           const sim::ClubLaunch& club = {});
  int size() const { return static_cast<int>(club_.size()); }
  /// [m/s] predicted launch speed for a club speed.
  double launch_speed(double club_speed) const;
  /// [rad] predicted launch angle minus hitting angle at a club speed.
  double angle_offset(double club_speed) const;
  /// The club speed in [lo, hi] whose predicted launch speed is nearest `launch_speed` (bisection;
  /// the relation is monotone over the envelope).
  double club_for(double launch_speed, double lo, double hi) const;
  /// How the ball leaves the club at a launch speed [m/s] (the putts' extras per unit launch
  /// speed, interpolated linearly in it, constant beyond the putts seen).
  sim::ClubLaunch club_launch(double launch_speed) const;
  /// Execution error as the fit sees it: std of the launch angle [rad] and of the launch speed
  /// relative to its prediction [-].
  double angle_std() const { return angle_std_; }
  double speed_std() const { return speed_std_; }

 private:
  void fit();
  std::vector<double> club_, launch_speed_, angle_residual_;
  std::vector<std::pair<double, sim::ClubLaunch>> per_speed_;  ///< (speed, extras / speed), sorted
  double gain_ = 1.6, offset_ = 0.0;
  bool has_gp_ = false;
  stats::GpModel speed_gp_, angle_gp_;
  double mean_angle_offset_ = 0.0;
  double angle_std_ = 0.0, speed_std_ = 0.0;
};

}  // namespace mg::game
