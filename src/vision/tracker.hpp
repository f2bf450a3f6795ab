#pragma once
/// The rolling ball's filter: a constant-velocity Kalman filter on the ball's horizontal position
/// (state x, y, vx, vy), time-stamped measurements, a gate on the innovation (an outlier is
/// refused, three in a row restart the track: the ball was struck). Free functions on a value
/// type; no allocation (real-time safe).
#include <Eigen/Dense>

namespace mg::vision {

struct TrackerConfig {
  double accel_std = 3.0;  ///< [m/s^2] white-noise acceleration (a struck ball jumps)
  double gate = 0.12;      ///< [m] an innovation beyond this (+ 3 sigma) is an outlier
  int restart_after = 3;   ///< outliers in a row that restart the track at the measurement
};

struct Track {
  bool initialised = false;
  double t = 0.0;                               ///< [s] time of the state
  double last_measured = -1e300;                ///< [s] time of the last accepted measurement
  Eigen::Vector4d x = Eigen::Vector4d::Zero();  ///< [m, m, m/s, m/s] world frame
  Eigen::Matrix4d P = Eigen::Matrix4d::Identity();
  int outliers_in_a_row = 0;
  long accepted = 0, rejected = 0;
};

/// Moves the state to time `t` (no-op for t <= track.t).
void track_predict(Track& track, const TrackerConfig& config, double t);
/// Predicts to `t` and fuses the measured position `z` [m] of standard deviation `sigma` [m].
/// Returns false when it was refused as an outlier.
bool track_update(Track& track, const TrackerConfig& config, double t, const Eigen::Vector2d& z,
                  double sigma);

}  // namespace mg::vision
