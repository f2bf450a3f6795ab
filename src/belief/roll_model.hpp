#pragma once
/// The belief's point model of a rolling ball (internal to src/belief; path_fit.hpp is the API):
/// MuJoCo's ball world written out for a point on a surface, with its soft contact, Penner's
/// rolling resistance and the spin a curved lane gives; and the path helpers the green fit uses
/// to cut a path where the model stops holding.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <variant>
#include <vector>

#include <Eigen/Dense>

#include "belief/path_fit.hpp"
#include "field/field.hpp"

namespace mg::belief::detail {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// [s] the longest RK4 step between two samples.
constexpr double kMaxStep = 0.01;
/// An interval whose RK4 steps see the acceleration jump by more than this [m/s^2] is
/// integrated in twice as many steps, up to kMaxRefine times (RK4 loses its order across a jump:
/// a hill's foot, where the curvature and with it the normal force jump, would leave an error of
/// 3e-5 m per crossing at 10 ms, and a fit that stalls on it).
constexpr double kJumpIndicator = 0.02;
constexpr int kMaxRefine = 32;
/// The ball-ground contact of the simulated world (src/sim/world_mjcf.cpp): solref (0.02 s, 1),
/// MuJoCo's default solimp (0.9, 0.95, 0.001, 0.5, 2): stiffness k = 1 / (dmax tc zeta)^2 and
/// damping b = 2 / (dmax tc) of its reference acceleration. A ball at rest sinks 0.37 mm.
constexpr double kSolimpMin = 0.9, kSolimpMax = 0.95, kSolimpWidth = 0.001;
constexpr double kContactTime = 0.02;
constexpr double kContactStiffness = 1.0 / (kSolimpMax * kSolimpMax * kContactTime * kContactTime);
constexpr double kContactDamping = 2.0 / (kSolimpMax * kContactTime);
constexpr double kGroundSink = 3.7e-4;  ///< [m] (the start of the settling iteration)
/// [m/s] The world's rolling resistance acts fully while the contact slips slower than half its
/// rolling_slip_limit (0.05 m/s, sim::WorldOptions), and the slip is measured at the ball's
/// radius, not at the lever: a rolling ball "slips" by v (r / lever - 1), 0.9 % of its speed at
/// rest, 2.5 % sunk 1 mm (a fast ball at a hill's foot). Where that nears half the limit, the
/// resistance fades and the path depends on details beyond the model (10 % more slip moved a
/// roll over the hill by 25 mm): such a path is cut where its slip would pass this.
constexpr double kMaxSlip = 0.02;
/// [m/s] the speed under which Penner's v/|v| is smoothed (keeps the model's stop stable at the
/// 10 ms step; far below the speeds the fit's samples keep to).
constexpr double kSpeedSmoothing = 0.005;
/// [m] step of the directional difference of the surface gradient (H v).
constexpr double kCurvatureStep = 2e-5;
/// A path needs this many rolling samples to enter the fit.
constexpr std::size_t kMinSamples = 8;
/// Slide margin: t_cut = kSlideFactor t* + kSlideMargin.
constexpr double kSlideFactor = 1.3;
constexpr double kSlideMargin = 0.05;
/// [s] a ball that would stop within this time (at the survey's rolling resistance x 1.25, up
/// the surveyed slope) is cut: near a stop, and where it may stall on a slope and roll back, the
/// path depends on the parameters too sharply to fit.
constexpr double kMinStopTime = 0.3;
/// A ball whose contact's normal force falls under this fraction of its weight may hop (a crest
/// taken fast): the path is cut there.
constexpr double kMinNormal = 0.5;
/// [s] half window of the speed estimate of a sample.
constexpr double kSpeedWindow = 0.05;

/// The point model over one lane and one green (see path_fit.hpp).
class RollModel {
 public:
  RollModel(const field::Field& field, double rho, std::array<double, 2> slope)
      : surface_(&field.surface),
        radius_(field.ball.radius),
        rho_(rho),
        sx_(slope[0]),
        sy_(slope[1]) {
    planar_ = std::all_of(
        field.surface.terms.begin(), field.surface.terms.end(),
        [](const field::SurfaceTerm& t) { return std::holds_alternative<field::PlaneTerm>(t); });
    if (planar_) plane_ = field.surface.gradient(0.0, 0.0);
    // A heightmap's gradient jumps at every cell: refining there would cost without end.
    refine_ = !planar_ && std::none_of(field.surface.terms.begin(), field.surface.terms.end(),
                                       [](const field::SurfaceTerm& t) {
                                         return std::holds_alternative<field::HeightmapTerm>(t);
                                       });
  }

  /// State: x, y, vx, vy, W (W = r times the spin about the surface normal [m/s]), and the
  /// soft contact's e (the ball's distance from the ground plane beyond its radius [m], < 0:
  /// sunk in) and de/dt.
  static constexpr int kDim = 7;
  using State = std::array<double, kDim>;

  /// Gradient of the surface the centre moves on at centre (x, y): the lane's (tilted) at the
  /// foot point, found as the world finds it (3 fixed-point steps from the centre).
  void gradient(double x, double y, double& gx, double& gy) const {
    if (planar_) {
      gx = plane_[0] + sx_;
      gy = plane_[1] + sy_;
      return;
    }
    double px = x, py = y;
    for (int it = 0; it < 3; ++it) {
      const auto g = surface_->gradient(px, py);
      gx = g[0] + sx_;
      gy = g[1] + sy_;
      const double k = radius_ / std::sqrt(1.0 + gx * gx + gy * gy);
      px = x + k * gx;
      py = y + k * gy;
    }
  }

  /// MuJoCo's impedance of the ball-ground contact at distance e (solimp's power sigmoid).
  static double impedance(double e) {
    const double x = std::min(1.0, std::abs(e) / kSolimpWidth);
    const double y = x <= 0.5 ? 2.0 * x * x : 1.0 - 2.0 * (1.0 - x) * (1.0 - x);
    return kSolimpMin + y * (kSolimpMax - kSolimpMin);
  }

  /// The surface under a state: gradient G, u = H v, c = v.u, q.
  struct Local {
    double gx, gy, ux, uy, c, q;
  };
  Local local(const State& s) const {
    Local l{};
    gradient(s[0], s[1], l.gx, l.gy);
    const double vx = s[2], vy = s[3], sp = std::hypot(vx, vy);
    if (!planar_ && sp > 0.0) {
      double hx, hy;
      gradient(s[0] + kCurvatureStep * vx / sp, s[1] + kCurvatureStep * vy / sp, hx, hy);
      l.ux = (hx - l.gx) * sp / kCurvatureStep;
      l.uy = (hy - l.gy) * sp / kCurvatureStep;
    }
    l.c = vx * l.ux + vy * l.uy;
    l.q = std::sqrt(1.0 + l.gx * l.gx + l.gy * l.gy);
    return l;
  }

  /// The state of a ball rolling as `start`, its contact settled (de/dt = 0, d2e/dt2 = 0).
  State initial(const RollState& start) const {
    State s{start.x, start.y, start.vx, start.vy, start.spin, 0.0, 0.0};
    const Local l = local(s);
    const double want = (kGravity + l.c) / l.q;  // N / m that keeps the ball on the surface
    double e = -kGroundSink;
    for (int it = 0; it < 20; ++it) {
      const double imp = impedance(e);
      e = -(want / imp - kGravity / l.q) / (kContactStiffness * imp);
    }
    s[5] = std::min(e, 0.0);
    return s;
  }

  State rate(const State& s) const {
    const double vx = s[2], vy = s[3], e = s[5], de = s[6];
    const Local l = local(s);
    const double q2 = l.q * l.q;
    const double sp2 = vx * vx + vy * vy;
    const double gv = l.gx * vx + l.gy * vy;
    // MuJoCo's soft contact (one normal constraint): N / m = imp (a_ref - a0.n), a_ref =
    // -b de/dt - k imp e; the ball's acceleration along the normal is a0.n + N / m.
    double normal = 0.0;
    if (e < 0.0) {
      const double imp = impedance(e);
      normal = std::max(
          0.0, imp * (-kContactDamping * de - kContactStiffness * imp * e + kGravity / l.q));
    }
    const double along_normal = normal - kGravity / l.q;
    // Friction acts midway through the sinking: the lever l = r + e / 2 sets the ball's
    // effective mass about the contact point, 1 + beta, beta = I / (m l^2).
    const double ratio = radius_ / (radius_ + 0.5 * std::min(e, 0.0));
    const double beta = 0.4 * ratio * ratio, roll = 1.0 / (1.0 + beta);
    const double resist =
        roll * ratio * rho_ * normal / std::sqrt(sp2 + gv * gv + kSpeedSmoothing * kSpeedSmoothing);
    const double push = (roll * kGravity / l.q + along_normal) / l.q;  // along -G
    const double spin = beta * roll * s[4] / q2;
    const double wx = (-vy - l.gy * gv) / l.q, wy = (vx + l.gx * gv) / l.q;
    return {vx,
            vy,
            -push * l.gx - resist * vx + spin * l.uy,
            -push * l.gy - resist * vy - spin * l.ux,
            -(wx * l.ux + wy * l.uy) / l.q,
            de,
            along_normal - l.c / l.q};
  }

  /// One RK4 step; returns the jump indicator |k1 - k2 - k3 + k4| of the acceleration [m/s^2]:
  /// h^2 / 4 |f''| where the rate is smooth, the size of a jump where it is not.
  double rk4(State& s, double h) const {
    const State k1 = rate(s);
    State t;
    for (int i = 0; i < kDim; ++i) t[i] = s[i] + 0.5 * h * k1[i];
    const State k2 = rate(t);
    for (int i = 0; i < kDim; ++i) t[i] = s[i] + 0.5 * h * k2[i];
    const State k3 = rate(t);
    for (int i = 0; i < kDim; ++i) t[i] = s[i] + h * k3[i];
    const State k4 = rate(t);
    for (int i = 0; i < kDim; ++i) s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    // The contact's own fast dynamics move its part (x 0.1: it reaches the path through the
    // slope only).
    double jump = 0.1 * std::abs(k1[6] - k2[6] - k3[6] + k4[6]);
    for (int i : {2, 3}) jump = std::max(jump, std::abs(k1[i] - k2[i] - k3[i] + k4[i]));
    return jump;
  }

  /// Positions at `n` times from `start` at times[0] into out[2 i], out[2 i + 1]. Each interval
  /// between samples is integrated in steps of at most kMaxStep; where the rate jumps within
  /// one (a surface whose curvature jumps, as a hill's foot), in up to kMaxRefine times as many
  /// (the steps of interval i go to / come from substeps[i] when `substeps` is given and
  /// `adapt` true / false). False if the state stopped being finite.
  bool simulate(const double* times, std::size_t n, const RollState& start, double* out,
                int* substeps = nullptr, bool adapt = true) const {
    State s = initial(start);
    out[0] = s[0];
    out[1] = s[1];
    for (std::size_t i = 1; i < n; ++i) {
      const double dt = times[i] - times[i - 1];
      int steps = std::max(1, static_cast<int>(std::ceil(dt / kMaxStep - 1e-9)));
      if (!adapt && substeps) {
        steps = substeps[i];
        const double h = dt / steps;
        for (int k = 0; k < steps; ++k) rk4(s, h);
      } else {
        const int most = kMaxRefine * steps;
        for (;;) {
          State t = s;
          double jump = 0.0;
          const double h = dt / steps;
          for (int k = 0; k < steps; ++k) jump = std::max(jump, rk4(t, h));
          if (jump > kJumpIndicator && steps < most && refine_) {
            steps *= 2;
            continue;
          }
          s = t;
          break;
        }
        if (substeps) substeps[i] = steps;
      }
      out[2 * i] = s[0];
      out[2 * i + 1] = s[1];
    }
    for (double v : s)
      if (!std::isfinite(v)) return false;
    return true;
  }

 private:
  const field::Surface* surface_;
  double radius_;
  double rho_, sx_, sy_;
  bool planar_ = false;
  bool refine_ = false;
  std::array<double, 2> plane_{0.0, 0.0};
};

/// Least-squares fit of a + b t + c t^2 to (t[i], y[i stride]) (c = 0 when `quadratic` is
/// false); the value and derivative at t = 0.
inline void poly_fit(const double* t, const double* y, std::size_t n, std::size_t stride,
                     bool quadratic, double& value, double& slope) {
  const int m = quadratic ? 3 : 2;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(n), m);
  Eigen::VectorXd b(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    a(r, 0) = 1.0;
    a(r, 1) = t[i];
    if (quadratic) a(r, 2) = t[i] * t[i];
    b(r) = y[i * stride];
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
  value = x(0);
  slope = x(1);
}

/// Least-squares quadratic through (t[i], y[2 i]): value, first and second derivative at t = 0.
inline void poly_fit3(const double* t, const double* y, std::size_t n, double& value, double& slope,
                      double& curvature) {
  Eigen::MatrixXd a(static_cast<Eigen::Index>(n), 3);
  Eigen::VectorXd b(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    a(r, 0) = 1.0;
    a(r, 1) = t[i];
    a(r, 2) = t[i] * t[i];
    b(r) = y[2 * i];
  }
  const Eigen::Vector3d x = a.colPivHouseholderQr().solve(b);
  value = x(0);
  slope = x(1);
  curvature = 2.0 * x(2);
}

/// Velocity [m/s] of the path around sample i (a chord over +- kSpeedWindow); false for a lone
/// sample.
inline bool velocity_at(const std::vector<std::array<double, 3>>& s, std::size_t i, double& vx,
                        double& vy) {
  std::size_t lo = i, hi = i;
  while (lo > 0 && s[i][0] - s[lo - 1][0] <= kSpeedWindow + 1e-9) --lo;
  while (hi + 1 < s.size() && s[hi + 1][0] - s[i][0] <= kSpeedWindow + 1e-9) ++hi;
  if (hi == lo) return false;
  const double dt = s[hi][0] - s[lo][0];
  vx = (s[hi][1] - s[lo][1]) / dt;
  vy = (s[hi][2] - s[lo][2]) / dt;
  return true;
}

/// True when a ball at (x, y) moving at (vx, vy) on the surveyed lane is about to stop or stall
/// (kMinStopTime). `normal`, `gravity_normal`: [m/s^2] the normal force per mass that keeps it
/// on the lane, (g + v'Hv) / q, and gravity's part of it, g / q.
inline bool about_to_stop(const field::Field& field, double x, double y, double vx, double vy,
                          double& normal, double& gravity_normal) {
  const double sp = std::hypot(vx, vy);
  const auto g = field.surface.gradient(x, y);
  const double q = std::sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
  gravity_normal = kGravity / q;
  normal = gravity_normal;
  if (!(sp > 0.0)) return true;
  const double ux = vx / sp, uy = vy / sp;
  const auto h = field.surface.gradient(x + kCurvatureStep * ux, y + kCurvatureStep * uy);
  const double curvature = ((h[0] - g[0]) * ux + (h[1] - g[1]) * uy) / kCurvatureStep;  // [1/m]
  normal = (kGravity + curvature * sp * sp) / q;
  const double decel = 5.0 / 7.0 * kGravity *
                       (1.25 * kRollingResistanceFactor * field.rolling_resistance +
                        kSlopeFactor * (g[0] * ux + g[1] * uy));
  return decel > 0.0 && sp < kMinStopTime * decel;
}

/// The soft contact along an observed path: its distance e and de/dt follow the normal force
/// the lane demands (MuJoCo's contact lags it by ~20 ms), so a crest taken fast can lift the
/// ball although the demand alone stays positive.
class ContactFilter {
 public:
  /// Settled under the demand `normal` [m/s^2].
  explicit ContactFilter(double normal) {
    for (int it = 0; it < 20; ++it) {
      const double imp = RollModel::impedance(e_);
      e_ = -(normal / imp - kGravity) / (kContactStiffness * imp);
    }
    e_ = std::min(e_, 0.0);
  }
  /// Advances by dt [s] with the demand and gravity's normal part going linearly from (n0, g0)
  /// to (n1, g1); returns the contact's normal force per mass at the end [m/s^2].
  double e() const { return e_; }
  double advance(double dt, double n0, double g0, double n1, double g1) {
    constexpr int kSteps = 8;
    const double h = dt / kSteps;
    double force = 0.0;
    for (int k = 0; k < kSteps; ++k) {
      const double f = (k + 1.0) / kSteps;
      force = this->force(g0 + f * (g1 - g0));
      // Semi-implicit Euler: stable at the contact's 48 rad/s for h <= 2.5 ms.
      de_ += h * (force - (n0 + f * (n1 - n0)));
      e_ += h * de_;
    }
    return this->force(g1);
  }

 private:
  double force(double gravity_normal) const {
    if (e_ >= 0.0) return 0.0;
    const double imp = RollModel::impedance(e_);
    return std::max(0.0,
                    imp * (-kContactDamping * de_ - kContactStiffness * imp * e_ + gravity_normal));
  }
  double e_ = -kGroundSink, de_ = 0.0;
};

}  // namespace mg::belief::detail
