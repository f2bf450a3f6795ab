#include "system/observe.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "core/error.hpp"
#include "robot/wam_params.hpp"
#include "sim/fast_putt.hpp"

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

namespace {

/// A far corner of the lane from every sample: where an imagined roll meets no cup.
std::array<double, 2> hole_clear_of(const field::Field& f,
                                    const std::vector<sim::BallSample>& path) {
  const double inset = 0.5 * f.hole.diameter + 0.02;
  std::array<double, 2> best = f.hole.position;
  double far = -1.0;
  for (const double x : {f.bounds[0] + inset, f.bounds[1] - inset})
    for (const double y : {f.bounds[2] + inset, f.bounds[3] - inset}) {
      try {
        field::check_hole_position(f, {x, y});
      } catch (const InputError&) {
        continue;  // not on the lane (an L's missing corner)
      }
      double near = std::numeric_limits<double>::infinity();
      for (const sim::BallSample& s : path) near = std::min(near, std::hypot(s.x - x, s.y - y));
      if (near > far) far = near, best = {x, y};
    }
  return best;
}

}  // namespace

SeenLaunch fit_launch_to_roll(const sim::World& believed, const std::vector<sim::BallSample>& path,
                              double at, const SeenLaunch& seen, double horizon) {
  if (!seen.seen) return seen;
  const field::Field& f = believed.field();
  // The roll up to its first meeting with a border or an obstacle: a bounce the cameras see
  // badly (the ball behind a wall, its blob on the wall's edge) would steer the fit.
  const double clear = f.ball.radius + 0.03;
  const auto& b = f.bounds;
  std::vector<const sim::BallSample*> used;
  for (const sim::BallSample& s : path) {
    if (s.t < at || s.t > at + horizon) continue;
    if (s.x < b[0] + clear || s.x > b[1] - clear || s.y < b[2] + clear || s.y > b[3] - clear) break;
    if (!used.empty() &&
        field::line_blocked(f, {used.back()->x, used.back()->y}, {s.x, s.y}, clear))
      break;
    used.push_back(&s);
  }
  if (used.size() < 5) return seen;
  const auto [x0, y0] = seen.position;
  const double heading = std::atan2(seen.velocity[1], seen.velocity[0]);
  const double planar = std::hypot(seen.velocity[0], seen.velocity[1]);
  const std::array<double, 2> hole = hole_clear_of(f, path);
  const sim::DataPtr d = believed.make_data();
  const auto n = static_cast<Eigen::Index>(used.size());
  // Residuals (imagined - seen) at the samples of a launch scaled by k and turned by delta.
  const auto residuals = [&](double k, double delta) {
    const double angle = std::remainder(heading + delta, 2.0 * robot::kPi);  // a request's range
    const auto g = f.surface.gradient(x0, y0);
    const double cz = g[0] * std::cos(angle) + g[1] * std::sin(angle);
    sim::PuttRequest q;
    q.start = seen.position;
    q.angle = angle;
    q.speed = k * planar * std::sqrt(1.0 + cz * cz);  // along the surface, as start_putt launches
    q.record_interval = 0.01;
    q.max_duration = horizon + 0.05;
    const sim::PuttOutcome p = sim::fast_putt(believed, d.get(), hole, q);
    Eigen::VectorXd r(2 * n);
    const auto& tr = p.trajectory;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double tau = used[static_cast<std::size_t>(i)]->t - at;
      std::array<double, 2> at_tau{tr.empty() ? x0 : tr.back().x, tr.empty() ? y0 : tr.back().y};
      for (std::size_t j = 1; j < tr.size(); ++j) {
        if (tr[j].t < tau) continue;
        const double w = (tau - tr[j - 1].t) / std::max(tr[j].t - tr[j - 1].t, 1e-9);
        at_tau = {tr[j - 1].x + w * (tr[j].x - tr[j - 1].x),
                  tr[j - 1].y + w * (tr[j].y - tr[j - 1].y)};
        break;
      }
      r(2 * i) = at_tau[0] - used[static_cast<std::size_t>(i)]->x;
      r(2 * i + 1) = at_tau[1] - used[static_cast<std::size_t>(i)]->y;
    }
    return r;
  };
  // Levenberg-Marquardt on (k, delta) within [0.7, 1.3] x [-0.05, 0.05] rad. A start the
  // planning path refuses (a seen position in a wall, off the lane) keeps the kinematic launch.
  double k = 1.0, delta = 0.0, lambda = 1e-3;
  Eigen::VectorXd r;
  try {
    r = residuals(k, delta);
  } catch (const InputError&) {
    return seen;
  }
  double cost = r.squaredNorm();
  constexpr double kStep = 1e-3, kTurn = 2e-4;
  bool converged = false;
  for (int it = 0; it < 10 && !converged; ++it) {
    Eigen::MatrixXd j(2 * n, 2);
    j.col(0) = (residuals(k + kStep, delta) - r) / kStep;
    j.col(1) = (residuals(k, delta + kTurn) - r) / kTurn;
    const Eigen::Matrix2d jtj = j.transpose() * j;
    const Eigen::Vector2d jtr = j.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 5 && !improved; ++tries) {
      Eigen::Matrix2d a = jtj;
      a.diagonal() += lambda * jtj.diagonal().cwiseMax(1e-12);
      const Eigen::Vector2d step = a.ldlt().solve(-jtr);
      if (!step.allFinite()) break;
      const double k1 = std::clamp(k + step(0), 0.7, 1.3);
      const double d1 = std::clamp(delta + step(1), -0.05, 0.05);
      const Eigen::VectorXd r1 = residuals(k1, d1);
      const double c1 = r1.squaredNorm();
      if (c1 < cost) {
        improved = true;
        converged = std::abs(k1 - k) < 1e-5 && std::abs(d1 - delta) < 1e-6;
        k = k1, delta = d1, r = r1, cost = c1;
        lambda = std::max(lambda * 0.3, 1e-6);
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }
  SeenLaunch out = seen;
  const double v = k * planar;
  out.velocity = {v * std::cos(heading + delta), v * std::sin(heading + delta)};
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
  // The launch whose roll in the robot's own ball world follows the path seen.
  const sim::World believed(system.field(), system.ball_world().options());
  SeenLaunch kinematic = launch_from_path(result.outcome.trajectory, delay);
  // A fast ball may land late in the cameras' view: read it from a longer start of the path
  // (the roll fit then sets its speed and direction).
  if (!kinematic.seen)
    kinematic = launch_from_path(result.outcome.trajectory, delay, 2.0 * kLaunchWindow);
  const SeenLaunch seen = fit_launch_to_roll(believed, result.outcome.trajectory, delay, kinematic);
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
