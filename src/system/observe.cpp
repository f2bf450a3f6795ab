#include "system/observe.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "robot/wam_params.hpp"

namespace mg::system {

bool paths_seen_by_perception(const System& system) {
  return static_cast<bool>(system.perception_factory());
}

SeenLaunch launch_from_path(const std::vector<sim::BallSample>& path, double at, double window) {
  SeenLaunch out;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Matrix<double, 3, 2> rhs = Eigen::Matrix<double, 3, 2>::Zero();
  int n = 0;
  double first = std::numeric_limits<double>::infinity();
  for (const sim::BallSample& s : path) {
    if (s.t < 0.0 || s.t > window) continue;
    // Centred on `at`: the constant is the position there, the linear term the velocity.
    const double u = s.t - at;
    const Eigen::Vector3d row(1.0, u, u * u);
    normal += row * row.transpose();
    rhs.col(0) += row * s.x;
    rhs.col(1) += row * s.y;
    first = std::min(first, s.t);
    ++n;
  }
  if (n < 3 || first > 0.6 * window) return out;
  const Eigen::LDLT<Eigen::Matrix3d> solve(normal);
  if (solve.info() != Eigen::Success) return out;
  const Eigen::Matrix<double, 3, 2> c = solve.solve(rhs);
  if (!c.allFinite()) return out;
  out.seen = true;
  out.position = {c(0, 0), c(0, 1)};
  out.velocity = {c(1, 0), c(1, 1)};
  return out;
}

void perceive_putt(const System& system, SystemData& data, control::FullPuttResult& result) {
  auto* eyes = dynamic_cast<PathObserver*>(data.perception.get());
  if (eyes == nullptr || !result.hit) return;
  result.outcome.trajectory = eyes->observe_path(system, result);
  // The stance's turn, from the launch as measured in both frames (the robot knows where it
  // stands; the result does not carry it).
  const double world_angle = std::atan2(result.launch_state.qvel[1], result.launch_state.qvel[0]);
  const double yaw = std::remainder(world_angle - result.launch.angle, 2.0 * robot::kPi);
  const double delay = control::FullPuttOptions{}.launch_delay;
  const SeenLaunch seen = launch_from_path(result.outcome.trajectory, delay);
  sim::BallState& s = result.launch_state;
  if (!seen.seen) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    result.launch = {nan, nan};
    s.qpos.fill(nan);
    s.qvel.fill(nan);
    return;
  }
  const field::Field& f = system.field();
  const auto [x, y] = seen.position;
  const auto [vx, vy] = seen.velocity;
  const auto g = f.surface.gradient(x, y);
  s.qpos = {x, y, f.height(x, y) + f.ball.radius, 1.0, 0.0, 0.0, 0.0};
  s.qvel = {vx, vy, g[0] * vx + g[1] * vy, 0.0, 0.0, 0.0};
  s.qacc_warmstart.fill(0.0);
  s.ground_normal = 0.0;
  result.launch = {std::remainder(std::atan2(vy, vx) - yaw, 2.0 * robot::kPi), std::hypot(vx, vy)};
}

}  // namespace mg::system
