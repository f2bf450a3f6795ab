#include "game/skill.hpp"

#include <algorithm>
#include <cmath>

#include "core/rng.hpp"

namespace mg::game {
namespace {

constexpr int kMinPointsForGp = 4;

stats::GpModel fit_1d(const std::vector<double>& x, const std::vector<double>& y) {
  Eigen::MatrixXd in(static_cast<Eigen::Index>(x.size()), 1);
  Eigen::VectorXd out(static_cast<Eigen::Index>(y.size()));
  for (std::size_t i = 0; i < x.size(); ++i) {
    in(static_cast<Eigen::Index>(i), 0) = x[i];
    out(static_cast<Eigen::Index>(i)) = y[i];
  }
  stats::GprOptions o;
  o.restarts = 3;
  o.length_scale_bounds = {0.2, 10.0};  // [m/s] club speed: the relation is smooth
  Rng rng(17);                          // a fixed stream: the same putts, the same skill
  return stats::fit_gpr(in, out, rng, o);
}

sim::ClubLaunch scaled(const sim::ClubLaunch& c, double k) {
  return {c.advance * k,
          c.lift * k,
          c.vertical_speed * k,
          {c.spin[0] * k, c.spin[1] * k, c.spin[2] * k}};
}

sim::ClubLaunch mix(const sim::ClubLaunch& a, const sim::ClubLaunch& b, double t) {
  const auto lerp = [t](double x, double y) { return x + t * (y - x); };
  return {lerp(a.advance, b.advance),
          lerp(a.lift, b.lift),
          lerp(a.vertical_speed, b.vertical_speed),
          {lerp(a.spin[0], b.spin[0]), lerp(a.spin[1], b.spin[1]), lerp(a.spin[2], b.spin[2])}};
}

}  // namespace

void LaunchSkill::add(double club_speed, double hitting_angle, double launch_angle,
                      double launch_speed, const sim::ClubLaunch& club) {
  if (launch_speed > 0.0) {
    const std::pair<double, sim::ClubLaunch> entry{launch_speed, scaled(club, 1.0 / launch_speed)};
    per_speed_.insert(
        std::upper_bound(per_speed_.begin(), per_speed_.end(), entry,
                         [](const auto& a, const auto& b) { return a.first < b.first; }),
        entry);
  }
  club_.push_back(club_speed);
  launch_speed_.push_back(launch_speed);
  angle_residual_.push_back(launch_angle - hitting_angle);
  fit();
}

void LaunchSkill::fit() {
  const auto n = static_cast<double>(club_.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0, sa = 0;
  for (std::size_t i = 0; i < club_.size(); ++i) {
    sx += club_[i], sy += launch_speed_[i], sxx += club_[i] * club_[i];
    sxy += club_[i] * launch_speed_[i], sa += angle_residual_[i];
  }
  const double det = n * sxx - sx * sx;
  if (club_.size() >= 2 && det > 1e-9 * n * sxx) {
    gain_ = (n * sxy - sx * sy) / det;
    offset_ = (sy - gain_ * sx) / n;
  } else if (sxx > 0) {
    gain_ = sxy / sxx, offset_ = 0.0;
  }
  mean_angle_offset_ = sa / n;
  has_gp_ = club_.size() >= kMinPointsForGp;
  if (has_gp_) {
    std::vector<double> speed_residual(club_.size()), angle_residual(club_.size());
    for (std::size_t i = 0; i < club_.size(); ++i) {
      speed_residual[i] = launch_speed_[i] - (gain_ * club_[i] + offset_);
      angle_residual[i] = angle_residual_[i] - mean_angle_offset_;
    }
    speed_gp_ = fit_1d(club_, speed_residual);
    angle_gp_ = fit_1d(club_, angle_residual);
    angle_std_ = angle_gp_.hyper.noise_std;
    const double mean_speed = sy / n;
    speed_std_ = speed_gp_.hyper.noise_std / mean_speed;
  } else {
    angle_std_ = speed_std_ = 0.0;
  }
}

double LaunchSkill::launch_speed(double club_speed) const {
  double v = gain_ * club_speed + offset_;
  if (has_gp_) v += stats::gp_predict(speed_gp_, Eigen::VectorXd::Constant(1, club_speed)).mean;
  return v;
}

double LaunchSkill::angle_offset(double club_speed) const {
  double a = mean_angle_offset_;
  if (has_gp_) a += stats::gp_predict(angle_gp_, Eigen::VectorXd::Constant(1, club_speed)).mean;
  return a;
}

sim::ClubLaunch LaunchSkill::club_launch(double u) const {
  if (per_speed_.empty() || !(u > 0.0)) return {};
  if (u <= per_speed_.front().first) return scaled(per_speed_.front().second, u);
  if (u >= per_speed_.back().first) return scaled(per_speed_.back().second, u);
  const auto hi = std::upper_bound(per_speed_.begin(), per_speed_.end(), u,
                                   [](double x, const auto& e) { return x < e.first; });
  const auto lo = hi - 1;
  const double t = (u - lo->first) / (hi->first - lo->first);
  sim::ClubLaunch c = scaled(mix(lo->second, hi->second, t), u);
  c.lift = std::max(0.0, c.lift);
  return c;
}

double LaunchSkill::club_for(double target, double lo, double hi) const {
  if (launch_speed(lo) >= target) return lo;
  if (launch_speed(hi) <= target) return hi;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (launch_speed(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace mg::game
