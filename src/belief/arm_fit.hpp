#pragma once
/// Identification of the arm from what it measures (docs/belief.md): the club speed
/// it reached against the one its own model reaches for the same command (plant key
/// `club_speed_scale`), and the ball's launch direction seen in the perceived path against the
/// one its own model gives the same hit (`launch_angle_bias`). Free functions over numbers: the
/// caller plays the hits and predicts them.
#include <array>
#include <limits>
#include <vector>

namespace mg::belief {

/// One hit as the arm saw it.
struct ArmObservation {
  double commanded_speed = 0.0;  ///< [m/s] the club speed asked for
  double reached_speed = 0.0;    ///< [m/s] the club speed reached (FullPuttResult::club.speed)
  /// [m/s] the club speed the robot's own model reaches for the same command; 0: the command.
  /// A speed <= 0 or not finite in commanded/reached: no speed observation.
  double predicted_speed = 0.0;
  /// [rad, world] the launch direction seen (path_direction of the perceived path) and the one
  /// the robot's own model predicts for the same hit (the same estimator on its predicted path).
  /// NaN in either: no angle observation.
  double observed_launch_angle = std::numeric_limits<double>::quiet_NaN();
  double predicted_launch_angle = std::numeric_limits<double>::quiet_NaN();
};

struct ArmEstimate {
  double club_speed_scale = 1.0;  ///< reached / predicted club speed, robust mean
  double club_speed_scale_std = std::numeric_limits<double>::infinity();  ///< its standard error
  double launch_angle_bias = 0.0;  ///< [rad] observed - predicted launch angle, robust mean
  double launch_angle_bias_std = std::numeric_limits<double>::infinity();  ///< [rad] std error
  int speed_observations = 0;
  int angle_observations = 0;
};

/// A robust mean (Huber, k = 1.345 robust std, scale from the median absolute deviation) and its
/// standard error (inf for fewer than 2 values; 0 values: mean 0). Deterministic.
std::array<double, 2> robust_mean(std::vector<double> values);

/// Means and standard errors of the club speed scale and the launch angle bias over the
/// observations that carry them (none: the identity, std inf). Throws InputError for a
/// negative or non-finite commanded speed.
ArmEstimate fit_arm(const std::vector<ArmObservation>& observations);

/// [rad, world] The direction in which a path leaves: the least-squares line (orthogonal
/// regression) through the samples (t, x, y) with t in [t_from, t_to], pointed the way the ball
/// went. NaN for fewer than 3 samples or no motion. Applied to the perceived path and to the
/// robot's predicted path of the same hit, the difference is the launch's error: the bends of
/// the lane both see cancel.
double path_direction(const std::vector<std::array<double, 3>>& samples, double t_from,
                      double t_to);

}  // namespace mg::belief
