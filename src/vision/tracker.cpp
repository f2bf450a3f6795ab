#include "vision/tracker.hpp"

#include <cmath>

namespace mg::vision {

void track_predict(Track& k, const TrackerConfig& c, double t) {
  if (!k.initialised || t <= k.t) return;
  const double dt = t - k.t;
  Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
  F(0, 2) = F(1, 3) = dt;
  const double q = c.accel_std * c.accel_std;
  Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();
  const double a = dt * dt * dt * dt / 4.0 * q, b = dt * dt * dt / 2.0 * q, d = dt * dt * q;
  Q(0, 0) = Q(1, 1) = a;
  Q(0, 2) = Q(2, 0) = Q(1, 3) = Q(3, 1) = b;
  Q(2, 2) = Q(3, 3) = d;
  k.x = F * k.x;
  k.P = F * k.P * F.transpose() + Q;
  k.t = t;
}

bool track_update(Track& k, const TrackerConfig& c, double t, const Eigen::Vector2d& z,
                  double sigma) {
  const double r = sigma * sigma;
  const auto restart = [&] {
    k.initialised = true;
    k.t = t;
    k.x << z, 0.0, 0.0;
    k.P = Eigen::Vector4d(r, r, 1.0, 1.0).asDiagonal();
    k.last_measured = t;
    k.outliers_in_a_row = 0;
    ++k.accepted;
    return true;
  };
  if (!k.initialised) return restart();
  track_predict(k, c, t);
  const Eigen::Vector2d innovation = z - k.x.head<2>();
  const Eigen::Matrix2d S = k.P.topLeftCorner<2, 2>() + r * Eigen::Matrix2d::Identity();
  const double spread = 3.0 * std::sqrt(S.trace());
  if (innovation.norm() > c.gate + spread) {
    ++k.rejected;
    if (++k.outliers_in_a_row >= c.restart_after) return restart();
    return false;
  }
  const Eigen::Matrix<double, 4, 2> K = k.P.leftCols<2>() * S.inverse();
  k.x += K * innovation;
  k.P -= K * k.P.topRows<2>();
  k.last_measured = t;
  k.outliers_in_a_row = 0;
  ++k.accepted;
  return true;
}

}  // namespace mg::vision
