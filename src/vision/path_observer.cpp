#include "vision/path_observer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "viz/image.hpp"

namespace mg::vision {
namespace {

/// The ball's centre at `t` [s from the contact] on the recorded trajectory (cubic Hermite
/// between the samples around it: positions and velocities both recorded). False past its end.
bool ball_at(const std::vector<sim::BallSample>& path, double t, Eigen::Vector3d& p) {
  if (path.empty() || t < path.front().t || t > path.back().t) return false;
  const auto b = std::lower_bound(path.begin(), path.end(), t,
                                  [](const sim::BallSample& s, double v) { return s.t < v; });
  if (b == path.begin()) {
    p = {b->x, b->y, b->z};
    return true;
  }
  const sim::BallSample& s1 = *b;
  const sim::BallSample& s0 = *(b - 1);
  const double h = s1.t - s0.t;
  if (!(h > 0.0)) {
    p = {s1.x, s1.y, s1.z};
    return true;
  }
  const double u = (t - s0.t) / h, u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
               h11 = u3 - u2;
  p = h00 * Eigen::Vector3d(s0.x, s0.y, s0.z) + h10 * h * Eigen::Vector3d(s0.vx, s0.vy, s0.vz) +
      h01 * Eigen::Vector3d(s1.x, s1.y, s1.z) + h11 * h * Eigen::Vector3d(s1.vx, s1.vy, s1.vz);
  return true;
}

}  // namespace

PathFrame path_frame(const StereoData& data, double stamp) {
  PathFrame f;
  f.stamp = stamp;
  f.views = data.last_ball.views;
  f.point = data.last_ball.point;
  // The track's last measurement is this frame's exactly when the filter took it.
  f.accepted = f.views > 0 && data.ball.initialised && data.ball.last_measured == stamp;
  return f;
}

RollStats watch_roll(RigRenderer& renderer, mjData* d, const StereoModel& model, StereoData& data,
                     const std::vector<sim::BallSample>& trajectory, double t_contact,
                     std::array<double, 2> hole, double first, double period,
                     std::vector<PathFrame>& frames) {
  RollStats stats;
  const sim::World& world = renderer.world();
  world.reset(d);
  world.set_hole(d, hole);
  const int qb = world.ids().ball_qpos;
  Eigen::Vector3d p;
  for (long k = 0;; ++k) {
    const double stamp = first + static_cast<double>(k) * period;
    if (!ball_at(trajectory, stamp - t_contact, p)) break;
    // A uniform white sphere: its orientation does not show, the recorded path has none.
    for (int i = 0; i < 3; ++i) d->qpos[qb + i] = p[i];
    d->qpos[qb + 3] = 1.0;
    d->qpos[qb + 4] = d->qpos[qb + 5] = d->qpos[qb + 6] = 0.0;
    d->time = stamp;
    const auto r0 = std::chrono::steady_clock::now();
    const viz::Image* images[2] = {&renderer.render(0, d), &renderer.render(1, d)};
    stats.render_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
    const double c0 = thread_cpu_seconds();
    stereo_frame(model, data, images, stamp);
    stats.cpu_seconds += thread_cpu_seconds() - c0;
    frames.push_back(path_frame(data, stamp));
    ++stats.frames;
    if (!frames.back().accepted) ++stats.lost;
  }
  return stats;
}

std::vector<sim::BallSample> path_samples(const std::vector<PathFrame>& frames, double t_contact,
                                          double half_window) {
  std::vector<const PathFrame*> seen;
  for (const PathFrame& f : frames)
    if (f.accepted && f.stamp >= t_contact - 1e-9) seen.push_back(&f);
  std::vector<sim::BallSample> out;
  out.reserve(seen.size());
  std::size_t lo = 0;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    const double ti = seen[i]->stamp;
    while (seen[lo]->stamp < ti - half_window) ++lo;
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();
    int n = 0;
    for (std::size_t j = lo; j < seen.size() && seen[j]->stamp <= ti + half_window; ++j) {
      // Inverse variances: a ball placed from one camera is three times less sure.
      const double w = seen[j]->views == 2 ? 1.0 : 1.0 / 9.0;
      const double u = seen[j]->stamp - ti;
      const Eigen::Vector3d row(1.0, u, u * u);
      normal += w * row * row.transpose();
      rhs += w * row * seen[j]->point.transpose();
      ++n;
    }
    if (n < 3) continue;
    const Eigen::LDLT<Eigen::Matrix3d> solve(normal);
    if (solve.info() != Eigen::Success) continue;
    const Eigen::Matrix3d c = solve.solve(rhs);  // rows: value, rate, curvature; columns: x, y, z
    if (!c.allFinite()) continue;
    out.push_back({ti - t_contact, c(0, 0), c(0, 1), c(0, 2), c(1, 0), c(1, 1), c(1, 2)});
  }
  return out;
}

}  // namespace mg::vision
