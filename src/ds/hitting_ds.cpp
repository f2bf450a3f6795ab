#include "ds/hitting_ds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"

namespace mg::ds {
namespace {

using Vec3 = Eigen::Vector3d;

// C1 ramp 0 -> 1 on [0, 1] with zero slope at both ends.
double smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

}  // namespace

Modulator parse_modulator(const std::string& name) {
  if (name == "constant") return Modulator::kConstant;
  if (name == "sine") return Modulator::kSine;
  throw InputError(fmt::format("modulator: expected 'constant' or 'sine', got '{}'", name));
}

std::string to_string(Modulator modulator) {
  return modulator == Modulator::kConstant ? "constant" : "sine";
}

double speed_modulator(Modulator modulator, double s_d, double d0, double r) {
  if (modulator == Modulator::kConstant) return s_d;
  if (r >= d0) return 1.0;
  // Half a period of a shifted sine: s(0) = s^d, s(d0) = 1, zero slope at both ends, monotone.
  const double w = std::sin(0.5 * std::numbers::pi * std::max(r, 0.0) / d0);
  return s_d + (1.0 - s_d) * w * w;
}

Eigen::Matrix3d rotation_about_z(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix3d r;
  r << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return r;
}

HittingDsData::HittingDsData(const HittingModel& model)
    : seds_ws_(model.seds_gmr().make_workspace()),
      strength_ws_(model.strength_gmr().make_workspace()),
      in3_(Eigen::VectorXd::Zero(3)),
      out3_(Eigen::VectorXd::Zero(3)),
      out1_(Eigen::VectorXd::Zero(1)) {
  set_command(model, HittingCommand{0.0, model.default_speed(), Modulator::kConstant,
                                    model.x_star() - 0.3 * model.psi0()});
}

void HittingDsData::set_command(const HittingModel& model, const HittingCommand& command) {
  require_in_range("angle", command.angle, -std::numbers::pi, std::numbers::pi);
  require_in_range("speed", command.speed, 1e-3, 20.0);
  if (!command.start.allFinite()) throw InputError("start: expected finite coordinates");
  const double d0 = (command.start - model.x_star()).norm();
  if (command.modulator == Modulator::kSine && !(d0 > 1e-3))
    throw InputError(fmt::format(
        "start: the sine modulator needs a start away from the ball (d0 > 1 mm), got d0 = {} m",
        d0));
  command_ = command;
  s_d_ = command.speed / model.default_speed();
  d0_ = std::max(d0, 1e-3);
  rot_ = rotation_about_z(command.angle);
  psi_ = rot_ * model.psi0();
}

double strength_factor(const HittingModel& model, HittingDsData& data, const Vec3& y) {
  data.in3_ = y;
  model.strength_gmr().predict_mean(data.in3_, data.out1_, data.strength_ws_);
  const double v0 = model.default_speed();
  const auto& s = model.settings();
  double v = data.out1_[0];
  v = std::isfinite(v) ? std::clamp(v, s.min_strength_fraction * v0, s.max_strength_fraction * v0)
                       : s.min_strength_fraction * v0;
  // Hold v(x*) near the ball so the impact speed does not depend on where the last tick lands.
  const double alpha = smoothstep((s.blend_outer - y.norm()) / (s.blend_outer - s.blend_inner));
  return (1.0 - alpha) * v + alpha * v0;
}

Vec3 target_field(const HittingModel& model, HittingDsData& data, const Vec3& y) {
  const Vec3& psi0 = model.psi0();
  const double r = y.norm();
  if (r < 1e-12) return psi0;
  data.in3_ = y;
  model.seds_gmr().predict_mean(data.in3_, data.out3_, data.seds_ws_);
  Vec3 f = data.out3_;
  const double fn = f.norm();
  // SEDS guarantees f . y < 0 away from x*; fall back to the straight line if f is unusable.
  Vec3 e = (std::isfinite(fn) && fn > 1e-12) ? Vec3(f / fn) : Vec3(-y / r);

  const auto& s = model.settings();
  const double along = y.dot(psi0);  // < 0 behind the ball
  const double cos_behind = -along / r;
  const double alpha =
      smoothstep((s.blend_outer - r) / (s.blend_outer - s.blend_inner)) *
      smoothstep((cos_behind - s.cone_cos_min) / (s.cone_cos_max - s.cone_cos_min));
  if (alpha > 0.0) {
    const Vec3 perp = y - along * psi0;
    // Inside the cone |along| >= cone_cos_min r > 0, so the ratio stays bounded.
    const Vec3 guide = (psi0 - s.line_exponent * perp / (-along)).normalized();
    e = ((1.0 - alpha) * e + alpha * guide).normalized();
  }
  return e;
}

Vec3 hitting_ds_velocity(const HittingModel& model, HittingDsData& data, const Vec3& x) {
  const Vec3 y_world = x - model.x_star();
  const Vec3 y = data.rot_.transpose() * y_world;  // back to the default frame
  const double s = speed_modulator(data.command_.modulator, data.s_d_, data.d0_, y_world.norm());
  return s * strength_factor(model, data, y) * (data.rot_ * target_field(model, data, y));
}

Vec3 hitting_velocity(const HittingModel& /*model*/, const HittingDsData& data) {
  return data.command().speed * data.direction();
}

bool ball_reached(const HittingModel& model, const HittingDsData& data, const Vec3& x,
                  double capture_radius) {
  const Vec3 y = x - model.x_star();
  return y.dot(data.direction()) >= 0.0 && y.norm() <= capture_radius;
}

void RolloutOptions::validate() const {
  require_in_range("dt", dt, 1e-5, 0.1);
  require_positive("max_duration", max_duration);
  require_positive("max_distance", max_distance);
  require_positive("reach_tolerance", reach_tolerance);
  require_in_range("capture_radius", capture_radius, reach_tolerance, 1.0);
}

RolloutResult rollout(const HittingModel& model, const HittingCommand& command,
                      const RolloutOptions& options) {
  options.validate();
  // The DS is a model of the hitting motion near x*; a start metres away is no motion of the arm
  // (and 1e308 overflows the error norms to inf).
  if (!command.start.allFinite() ||
      (command.start - model.x_star()).norm() > kMaxRolloutStartDistance)
    throw InputError(
        fmt::format("rollout: start: expected a finite point within {} m of x* ({}, {}, {}), got "
                    "({}, {}, {})",
                    kMaxRolloutStartDistance, model.x_star()[0], model.x_star()[1],
                    model.x_star()[2], command.start[0], command.start[1], command.start[2]));
  HittingDsData data(model);
  data.set_command(model, command);
  RolloutResult res;
  const Vec3& psi = data.direction();
  const Vec3& xs = model.x_star();
  const double h = options.dt;
  Vec3 x = command.start;
  Vec3 v = hitting_ds_velocity(model, data, x);
  double t = 0.0;
  const auto record = [&](double tt, const Vec3& xx, const Vec3& vv) {
    if (!options.record) return;
    res.t.push_back(tt);
    res.x.push_back(xx);
    res.xdot.push_back(vv);
  };
  record(t, x, v);
  if ((x - xs).dot(psi) >= 0.0 && (x - xs).norm() <= options.reach_tolerance) {
    // Already at the ball.
    res.reached = true;
    res.stop_reason = "reached";
    res.position_error = (x - xs).norm();
    res.hit_position = x;
    res.velocity = v;
    return res;
  }
  const auto max_steps = static_cast<long>(std::ceil(options.max_duration / h));
  for (long step = 0; step < max_steps; ++step) {
    // Impact within the next tick? Decided on the straight segment x + u h v, u in [0, 1.5]:
    // near the ball the DS is a straight line at constant speed, and RK4 stages past the hitting
    // plane would sample the field that turns back toward x* (the controller switches there).
    const Vec3 y0 = x - xs, d = h * v;
    constexpr double kLookahead = 1.5;
    double u = -1.0;
    const double a0 = y0.dot(psi), ad = d.dot(psi);
    if (a0 < 0.0 && a0 + kLookahead * ad >= 0.0 &&
        (y0 + (-a0 / ad) * d).norm() <= options.capture_radius) {
      u = -a0 /
          ad;  // crosses the hitting plane at the ball (far from it, a crossing is just a pass)
    } else if (d.squaredNorm() > 0.0) {
      // Distance to x* stops decreasing within the tick: closest approach (e.g. from the side).
      const double uc = -y0.dot(d) / d.squaredNorm();
      if (uc >= 0.0 && uc < kLookahead && (y0 + uc * d).norm() <= options.reach_tolerance) u = uc;
    }
    if (u >= 0.0) {
      res.hit_position = x + u * d;
      res.velocity = v;  // the command of the last tick before impact
      res.position_error = (res.hit_position - xs).norm();
      res.duration = t + u * h;
      res.reached = res.position_error <= options.reach_tolerance;
      res.stop_reason = res.reached ? "reached" : "missed";
      record(res.duration, res.hit_position, res.velocity);
      return res;
    }
    const Vec3 k1 = v;
    const Vec3 k2 = hitting_ds_velocity(model, data, x + 0.5 * h * k1);
    const Vec3 k3 = hitting_ds_velocity(model, data, x + 0.5 * h * k2);
    const Vec3 k4 = hitting_ds_velocity(model, data, x + h * k3);
    const Vec3 x_next = x + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    const Vec3 v_next = hitting_ds_velocity(model, data, x_next);
    ++res.steps;
    x = x_next;
    v = v_next;
    t += h;
    record(t, x, v);
    if (!x.allFinite() || (x - xs).norm() > options.max_distance) {
      res.stop_reason = "diverged";
      res.duration = t;
      res.position_error = (x - xs).norm();
      res.hit_position = x;
      res.velocity = v;
      return res;
    }
  }
  res.stop_reason = "timeout";
  res.duration = t;
  res.position_error = (x - xs).norm();
  res.hit_position = x;
  res.velocity = v;
  return res;
}

std::string format_rollout(const RolloutResult& result) {
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < result.t.size(); ++i)
    rows.push_back({result.t[i], result.x[i].x(), result.x[i].y(), result.x[i].z(),
                    result.xdot[i].x(), result.xdot[i].y(), result.xdot[i].z()});
  return format_csv({"t", "x", "y", "z", "vx", "vy", "vz"}, rows);
}

ReproductionError reproduction_error(const HittingModel& model,
                                     const std::vector<Demonstration>& demos) {
  ReproductionError err;
  HittingDsData data(model);
  data.set_command(model, HittingCommand{0.0, model.default_speed(), Modulator::kConstant,
                                         model.x_star() - 0.3 * model.psi0()});
  double sum_v = 0.0, sum_a = 0.0, sum_sa = 0.0, sum_sp = 0.0, sum_path = 0.0;
  long n_v = 0, n_path = 0;
  for (const auto& d : demos) {
    for (std::size_t i = 0; i < d.size(); ++i) {
      // Slow samples carry no direction; within 2 cm of x* the field turns with millimetre position
      // noise (0.3 mm at 3 mm is ~17 degrees of the guidance), which says nothing about the fit.
      if (d.xdot[i].norm() < 0.05 * model.default_speed() ||
          (d.x[i] - model.x_star()).norm() < 0.02)
        continue;
      const Vec3 v = hitting_ds_velocity(model, data, d.x[i]);
      sum_v += (v - d.xdot[i]).squaredNorm();
      const double c = std::clamp(v.normalized().dot(d.xdot[i].normalized()), -1.0, 1.0);
      sum_a += std::pow(std::acos(c), 2);
      const Eigen::VectorXd f =
          model.seds_gmr().predict(Eigen::VectorXd(d.x[i] - model.x_star())).mean;
      sum_sa +=
          std::pow(std::acos(std::clamp(f.normalized().dot(d.xdot[i].normalized()), -1.0, 1.0)), 2);
      sum_sp += std::pow(v.norm() - d.xdot[i].norm(), 2);
      ++n_v;
    }
    HittingCommand cmd{0.0, model.default_speed(), Modulator::kConstant, d.x.front()};
    const RolloutResult r = rollout(model, cmd);
    if (r.reached) ++err.all_reached;
    for (const auto& p : d.x) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j + 1 < r.x.size(); ++j) {
        const Vec3 seg = r.x[j + 1] - r.x[j];
        const double u = seg.squaredNorm() > 0
                             ? std::clamp((p - r.x[j]).dot(seg) / seg.squaredNorm(), 0.0, 1.0)
                             : 0.0;
        best = std::min(best, (p - (r.x[j] + u * seg)).norm());
      }
      if (r.x.size() == 1) best = (p - r.x[0]).norm();
      sum_path += best;
      err.max_path_distance = std::max(err.max_path_distance, best);
      ++n_path;
    }
  }
  err.velocity_rmse = n_v ? std::sqrt(sum_v / static_cast<double>(n_v)) : 0.0;
  err.direction_rmse = n_v ? std::sqrt(sum_a / static_cast<double>(n_v)) : 0.0;
  err.seds_direction_rmse = n_v ? std::sqrt(sum_sa / static_cast<double>(n_v)) : 0.0;
  err.speed_rmse = n_v ? std::sqrt(sum_sp / static_cast<double>(n_v)) : 0.0;
  err.mean_path_distance = n_path ? sum_path / static_cast<double>(n_path) : 0.0;
  return err;
}

}  // namespace mg::ds
