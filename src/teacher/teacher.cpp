#include "teacher/teacher.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "core/error.hpp"
#include "teacher/bank_shots.hpp"

namespace mg::teacher {

TeacherOptions options_for(const field::Situations& region, const std::string& strategy) {
  TeacherOptions t;
  t.strategy = parse_strategy(strategy.empty() ? region.strategy : strategy);
  t.learn_speed = region.learn_speed;
  t.fixed_speed = region.speed;
  return t;
}

namespace {

constexpr double kLaunchBias = -0.006;  ///< [rad] measured launch angle - theta (docs/control.md)
constexpr double kLaunchRatio = 1.6;    ///< measured launch speed / club speed (1.54-1.67)
/// [rad] how far a search may turn from where it starts (the fixed arm's envelope is 0.9 wide;
/// the base turns for hits beyond it, so the search is bounded round its start instead).
constexpr double kAngleReach = 0.6;
/// [rad] a bank's search stays this close to its folded path's aim (further, it is another path).
constexpr double kBankReach = 0.1;

/// One putt, seen the way the teacher uses it.
struct Probe {
  bool valid = false;  ///< the ball was launched (the club hit it) and its outcome is known
  bool sunk = false;
  Eigen::Vector2d r = Eigen::Vector2d::Zero();  ///< residual (lateral [m], e - v_t^2 [m^2/s^2])
  double launch_angle = 0.0, launch_speed = 0.0, approach_speed = 0.0;
};

/// The search state of one situation.
class Search {
 public:
  Search(const system::System& system, system::SystemData& data, const field::Situation& situation,
         const TeacherOptions& options)
      : sys_(system),
        data_(data),
        hole_(situation.hole),
        ball_(situation.ball),
        on_tee_(situation.ball == system.field().tee),
        opt_(options) {
    const auto& f = system.field();
    const auto hole = hole_;
    dx_ = hole[0] - ball_[0];
    dy_ = hole[1] - ball_[1];
    distance_ = std::hypot(dx_, dy_);
    a_roll_ = belief::rolling_deceleration(f);
    vt_ = arrival_speed(f, options.strategy);
    radius_ = 0.5 * f.hole.diameter;
    const belief::LaunchGuess prior = belief::prior_launch(f, ball_, hole, vt_);
    aim_ = prior.angle;
    prior_launch_speed_ = prior.speed;
    lateral_gain_ = -distance_;
    if (field::line_blocked(f, ball_, hole, f.ball.radius))
      banks_ = bank_shots(f, ball_, hole, vt_);
    if (!banks_.empty()) {  // the shortest bank until a search tries the others
      aim_ = banks_.front().angle;
      distance_ = banks_.front().path_length;
      lateral_gain_ = banks_.front().lateral_gain();
      prior_launch_speed_ = banks_.front().launch_speed;
    }
  }

  Probe residual(const sim::PuttOutcome& o) const {
    Probe p;
    p.valid = o.end != sim::PuttEnd::kTimeOut || o.sunk;
    p.sunk = o.sunk;
    const double e =
        o.approach_speed * o.approach_speed - 2.0 * a_roll_ * std::max(0.0, o.approach_along);
    p.r = {o.approach_lateral, e - vt_ * vt_};
    p.approach_speed = o.approach_speed;
    return p;
  }

  Probe ball(double angle, double speed) {
    ++ex_.ball_putts;
    return residual(system::ball_putt(sys_, data_, hole_, angle, speed, 0.0,
                                      on_tee_ ? std::nullopt : std::optional(ball_)));
  }

  /// A club the arm can hit from some stance (the base turns beyond the fixed arm's envelope:
  /// system::hit_pose).
  std::pair<double, double> clamp_club(double angle, double speed) const {
    const auto& c = sys_.config();
    speed = std::clamp(speed, c.speed_min, max_club_speed());
    return {angle, speed};
  }

  double max_club_speed() const {
    return std::min(sys_.config().speed_max, sys_.module().club_speed_cap());
  }

  Probe full(double angle, double speed) {
    ++ex_.full_putts;
    const control::FullPuttResult r = system::arm_hit(sys_, data_, {ball_, hole_}, angle, speed);
    if (!r.hit || r.hit_refused) return {};
    Probe p = residual(r.outcome);
    p.launch_angle = r.launch.angle;
    p.launch_speed = r.launch.speed;
    return p;
  }

  bool converged(const Probe& p) const {
    return p.sunk && std::abs(p.r[0]) < 0.25 * radius_ && std::abs(p.r[1]) < 0.35 * vt_ * vt_;
  }

  /// Broyden's method on the residual over x = (angle, speed); `probe` runs a putt. Returns the
  /// converged point, else the best sinking point seen (smallest residual), else nothing.
  template <typename ProbeFn>
  std::optional<Eigen::Vector2d> solve(Eigen::Vector2d x, Eigen::Matrix2d jac, int max_iter,
                                       ProbeFn probe, Eigen::Vector2d lo, Eigen::Vector2d hi,
                                       bool one_d, Probe* last = nullptr) {
    std::optional<Eigen::Vector2d> best;
    double best_score = 1e300;
    Probe p = probe(x);
    for (int it = 0; it < max_iter; ++it) {
      if (!p.valid) return best;
      const double score =
          std::abs(p.r[0]) / radius_ + (one_d ? 0.0 : std::abs(p.r[1]) / (vt_ * vt_));
      if (p.sunk && score < best_score) {
        best = x;
        best_score = score;
        if (last) *last = p;
      }
      if (one_d ? (p.sunk && std::abs(p.r[0]) < 0.25 * radius_) : converged(p)) return x;
      Eigen::Vector2d step;
      if (one_d) {
        step = {-p.r[0] / jac(0, 0), 0.0};
      } else {
        step = -jac.fullPivLu().solve(p.r);
        if (!step.allFinite()) return best;
      }
      step[0] = std::clamp(step[0], -0.08, 0.08);
      step[1] = std::clamp(step[1], -0.3 * x[1], 0.3 * x[1]);
      Eigen::Vector2d xn = (x + step).cwiseMax(lo).cwiseMin(hi);
      const Eigen::Vector2d dx = xn - x;
      if (dx.norm() < 1e-7) return best;
      const Probe pn = probe(xn);
      if (!pn.valid) return best;
      // Broyden's rank-one update (one_d: the secant).
      const Eigen::Vector2d dr = pn.r - p.r;
      if (one_d) {
        if (std::abs(dx[0]) > 1e-9 && std::abs(dr[0] / dx[0]) > 1e-3 &&
            (dr[0] / dx[0]) * jac(0, 0) > 0.0)  // the slope keeps its sign (a bank flips it)
          jac(0, 0) = dr[0] / dx[0];
      } else {
        jac += (dr - jac * dx) * dx.transpose() / dx.squaredNorm();
      }
      x = xn;
      p = pn;
    }
    if (p.valid && p.sunk) {
      const double score =
          std::abs(p.r[0]) / radius_ + (one_d ? 0.0 : std::abs(p.r[1]) / (vt_ * vt_));
      if (score < best_score) {
        best = x;
        if (last) *last = p;
      }
    }
    return best;
  }

  /// Stage 1: a sinking launch (angle, speed) on the ball-only path. The direct line, unless an
  /// obstacle blocks it; then the bank shots off a border, shortest path first.
  std::optional<Eigen::Vector2d> propose() {
    const auto probe = [&](const Eigen::Vector2d& x) { return ball(x[0], x[1]); };
    if (banks_.empty()) {
      const Eigen::Vector2d x0(aim_, prior_launch_speed_);
      Eigen::Matrix2d j;
      j << lateral_gain_, 0.0, 0.0, 2.0 * 25.0 / 49.0 * prior_launch_speed_;
      const Eigen::Vector2d lo(aim_ - 0.6, 0.2), hi(aim_ + 0.6, 6.0);
      if (auto x = solve(x0, j, 14, probe, lo, hi, false)) return x;
      return grid_proposal();
    }
    for (const BankShot& b : banks_) {
      if (ex_.ball_putts + 14 > opt_.max_ball_putts) break;
      aim_ = b.angle;
      distance_ = b.path_length;
      lateral_gain_ = b.lateral_gain();
      Eigen::Matrix2d j;
      j << lateral_gain_, 0.0, 0.0, 2.0 * 25.0 / 49.0 * b.launch_speed;
      const Eigen::Vector2d lo(b.angle - kBankReach, 0.2), hi(b.angle + kBankReach, 6.0);
      if (auto x = solve(Eigen::Vector2d(b.angle, b.launch_speed), j, 14, probe, lo, hi, false))
        return x;
    }
    return std::nullopt;
  }

  /// Fallback of stage 1: a coarse grid around the aim; the strategy's pick among sinking cells
  /// that have a sinking neighbour.
  std::optional<Eigen::Vector2d> grid_proposal() {
    const int na = 41, nu = 12;
    std::vector<char> sunk(static_cast<std::size_t>(na * nu), 0);
    const auto angle = [&](int i) { return aim_ - 0.2 + 0.01 * i; };
    const auto speed = [&](int k) { return prior_launch_speed_ * (0.7 + 0.07 * k); };
    for (int i = 0; i < na && ex_.ball_putts < opt_.max_ball_putts; ++i)
      for (int k = 0; k < nu && ex_.ball_putts < opt_.max_ball_putts; ++k)
        sunk[static_cast<std::size_t>(i * nu + k)] = ball(angle(i), speed(k)).sunk;
    std::optional<Eigen::Vector2d> best;
    double best_key = 1e300;
    for (int i = 0; i < na; ++i)
      for (int k = 0; k < nu; ++k) {
        if (!sunk[static_cast<std::size_t>(i * nu + k)]) continue;
        const bool neighbour = (i > 0 && sunk[static_cast<std::size_t>((i - 1) * nu + k)]) ||
                               (i + 1 < na && sunk[static_cast<std::size_t>((i + 1) * nu + k)]) ||
                               (k > 0 && sunk[static_cast<std::size_t>(i * nu + k - 1)]) ||
                               (k + 1 < nu && sunk[static_cast<std::size_t>(i * nu + k + 1)]);
        if (!neighbour) continue;
        const double da = std::abs(angle(i) - aim_);
        const double key =
            opt_.strategy == Strategy::kMinSpeed ? speed(k) * 100.0 + da : da * 100.0 + speed(k);
        if (key < best_key) {
          best_key = key;
          best = Eigen::Vector2d(angle(i), speed(k));
        }
      }
    grid_used_ = best.has_value();
    return best;
  }

  /// Stage 2: from a ball-only launch to a sinking club (angle, speed) on the full system.
  std::optional<Eigen::Vector2d> full_solve(const Eigen::Vector2d& launch) {
    double theta = launch[0] - kLaunchBias, v = launch[1] / kLaunchRatio;
    // Match the measured launch to the proposal (the launch relation of this very arm).
    Probe p;
    for (int it = 0; it < 3; ++it) {
      std::tie(theta, v) = clamp_club(theta, v);
      p = full(theta, v);
      if (!p.valid) return std::nullopt;
      if (grid_used_ && p.sunk) return Eigen::Vector2d(theta, v);
      if (converged(p)) return Eigen::Vector2d(theta, v);
      theta += launch[0] - p.launch_angle;
      v *= launch[1] / std::max(p.launch_speed, 1e-3);
    }
    if (grid_used_) return std::nullopt;
    Eigen::Matrix2d j;
    j << lateral_gain_, 0.0, 0.0, 2.0 * 25.0 / 49.0 * launch[1] * kLaunchRatio;
    const auto& c = sys_.config();
    const auto probe = [&](const Eigen::Vector2d& x) {
      const auto [a, s] = clamp_club(x[0], x[1]);
      return full(a, s);
    };
    const Eigen::Vector2d lo(launch[0] - kAngleReach, c.speed_min),
        hi(launch[0] + kAngleReach, max_club_speed());
    return solve(Eigen::Vector2d(theta, v), j,
                 std::max(2, opt_.max_full_putts - ex_.full_putts - 6), probe, lo, hi, false);
  }

  /// From a neighbour-derived club (the continuity hint): Broyden on the full system.
  std::optional<Eigen::Vector2d> hinted_solve() {
    const auto& c = sys_.config();
    Eigen::Matrix2d j;
    j << lateral_gain_, 0.0, 0.0, 2.0 * 25.0 / 49.0 * opt_.hint[1] * kLaunchRatio * kLaunchRatio;
    const auto probe = [&](const Eigen::Vector2d& x) {
      const auto [a, s] = clamp_club(x[0], x[1]);
      return full(a, s);
    };
    const Eigen::Vector2d lo(opt_.hint[0] - kAngleReach, c.speed_min),
        hi(opt_.hint[0] + kAngleReach, max_club_speed());
    return solve(Eigen::Vector2d(opt_.hint[0], opt_.hint[1]), j,
                 std::max(2, opt_.max_full_putts - 6), probe, lo, hi, false);
  }

  /// Angle only: the secant on the lateral miss at the fixed club speed, on the full system.
  std::optional<Eigen::Vector2d> angle_solve() {
    Eigen::Matrix2d j;
    j << lateral_gain_, 0.0, 0.0, 1.0;
    const double v = opt_.fixed_speed;
    const auto probe = [&](const Eigen::Vector2d& x) { return full(x[0], v); };
    const double start = opt_.use_hint ? opt_.hint[0] : aim_ - kLaunchBias;
    return solve(Eigen::Vector2d(start, v), j, std::max(2, opt_.max_full_putts - 6), probe,
                 Eigen::Vector2d(start - kAngleReach, v), Eigen::Vector2d(start + kAngleReach, v),
                 true);
  }

  /// Verifies (and if needed re-centres) the neighbourhood of a sinking point.
  void settle_margin(double theta, double v) {
    double da = opt_.margin_angle, dv = opt_.learn_speed ? opt_.margin_speed : 0.0;
    for (int round = 0; round < 4; ++round) {
      const auto [a, s] = clamp_club(theta, v);
      theta = a;
      v = opt_.learn_speed ? s : opt_.fixed_speed;
      const Probe centre = full(theta, v);
      if (!centre.sunk) break;
      record(theta, v, centre, 0.0, 0.0);
      const bool a_minus = full(theta - da, v).sunk, a_plus = full(theta + da, v).sunk;
      bool s_minus = true, s_plus = true;
      if (dv > 0.0) {
        s_minus = full(theta, v - dv).sunk;
        s_plus = full(theta, v + dv).sunk;
      }
      if (a_minus && a_plus && s_minus && s_plus) {
        record(theta, v, centre, da, dv);
        return;
      }
      if (a_minus != a_plus)
        theta += a_plus ? 0.5 * da : -0.5 * da;
      else if (!a_minus)
        da *= 0.5;
      if (dv > 0.0) {
        if (s_minus != s_plus)
          v += s_plus ? 0.5 * dv : -0.5 * dv;
        else if (!s_minus)
          dv *= 0.5;
      }
      if (ex_.full_putts + 5 > opt_.max_full_putts + 10) return;
    }
  }

  void record(double theta, double v, const Probe& p, double da, double dv) {
    ex_.found = true;
    ex_.angle = theta;
    ex_.speed = v;
    ex_.margin_angle = da;
    ex_.margin_speed = dv;
    ex_.launch_angle = p.launch_angle;
    ex_.launch_speed = p.launch_speed;
    ex_.approach_speed = p.approach_speed;
  }

  Example run() {
    ex_.hole = hole_;
    ex_.ball = ball_;
    std::optional<Eigen::Vector2d> club;
    if (opt_.learn_speed && opt_.use_hint) {
      club = hinted_solve();
    } else if (opt_.learn_speed) {
      if (const auto launch = propose()) club = full_solve(*launch);
    } else {
      club = angle_solve();
    }
    if (club) settle_margin((*club)[0], opt_.learn_speed ? (*club)[1] : opt_.fixed_speed);
    return ex_;
  }

 private:
  const system::System& sys_;
  system::SystemData& data_;
  std::array<double, 2> hole_, ball_;
  bool on_tee_ = true;  ///< ball-only putts start at the tee without a start point
  TeacherOptions opt_;
  double dx_ = 0, dy_ = 0, distance_ = 1, aim_ = 0, a_roll_ = 0, vt_ = 0.5, radius_ = 0.054;
  double prior_launch_speed_ = 1.0;
  double lateral_gain_ = -1.0;   ///< d(lateral miss)/d(launch angle) [m/rad] at the start
  std::vector<BankShot> banks_;  ///< when an obstacle blocks the direct line
  bool grid_used_ = false;
  Example ex_;
};

}  // namespace

std::string to_string(Strategy s) { return s == Strategy::kMinSpeed ? "min-speed" : "min-angle"; }

Strategy parse_strategy(const std::string& name) {
  if (name == "min-speed") return Strategy::kMinSpeed;
  if (name == "min-angle") return Strategy::kMinAngle;
  throw InputError(fmt::format("strategy: expected min-speed or min-angle, got '{}'", name));
}

void TeacherOptions::validate() const {
  if (!learn_speed && !(fixed_speed > 0.0 && std::isfinite(fixed_speed)))
    throw InputError(
        fmt::format("teacher: fixed club speed: expected > 0 m/s, got {}", fixed_speed));
  if (!(margin_angle >= 0.0 && margin_angle <= 0.1))
    throw InputError(
        fmt::format("teacher: margin_angle: expected 0..0.1 rad, got {}", margin_angle));
  if (!(margin_speed >= 0.0 && margin_speed <= 0.5))
    throw InputError(
        fmt::format("teacher: margin_speed: expected 0..0.5 m/s, got {}", margin_speed));
  if (max_full_putts < 1 || max_ball_putts < 0)
    throw InputError("teacher: putt budgets: expected >= 1 full-system and >= 0 ball-only putts");
}

double arrival_speed(const field::Field& field, Strategy strategy) {
  if (strategy == Strategy::kMinSpeed) return kMinSpeedArrival;
  // A shallow cup holds only slower balls (docs/physics.md, "Capture at the hole": a 15 mm cup
  // sinks about 0.7x the speeds of a 60 mm one at the same offset), so the fast arrival scales with
  // depth.
  const double depth_factor = std::clamp(field.hole.depth / 0.06, 0.5, 1.0);
  return std::max(kMinSpeedArrival, kMinAngleArrival * depth_factor);
}

Example teach(const system::System& system, system::SystemData& data, std::array<double, 2> hole,
              const TeacherOptions& options) {
  return teach(system, data, field::Situation{system.field().tee, hole}, options);
}

Example teach(const system::System& system, system::SystemData& data,
              const field::Situation& situation, const TeacherOptions& options) {
  options.validate();
  field::check_hole_position(system.field(), situation.hole);
  field::check_ball_position(system.field(), situation.ball, "teacher: ball");
  return Search(system, data, situation, options).run();
}

}  // namespace mg::teacher
