#include "belief/path_fit.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "core/error.hpp"

namespace mg::belief {
namespace {

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
void poly_fit(const double* t, const double* y, std::size_t n, std::size_t stride, bool quadratic,
              double& value, double& slope) {
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
void poly_fit3(const double* t, const double* y, std::size_t n, double& value, double& slope,
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
bool velocity_at(const std::vector<std::array<double, 3>>& s, std::size_t i, double& vx,
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
bool about_to_stop(const field::Field& field, double x, double y, double vx, double vy,
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

void check_path(const ObservedPath& p, std::size_t index) {
  for (std::size_t j = 0; j < p.samples.size(); ++j) {
    const auto& s = p.samples[j];
    if (!std::isfinite(s[0]) || !std::isfinite(s[1]) || !std::isfinite(s[2]))
      throw InputError(
          fmt::format("fit_green: paths[{}].samples[{}]: expected finite (t, x, y), "
                      "got ({}, {}, {})",
                      index, j, s[0], s[1], s[2]));
    if (j > 0 && !(s[0] > p.samples[j - 1][0]))
      throw InputError(
          fmt::format("fit_green: paths[{}].samples[{}]: expected times ascending, got {} after {}",
                      index, j, s[0], p.samples[j - 1][0]));
  }
  if (p.hole && !(std::isfinite((*p.hole)[0]) && std::isfinite((*p.hole)[1])))
    throw InputError(fmt::format("fit_green: paths[{}].hole: expected a finite position", index));
}

/// One path's data in the fit.
struct FitPath {
  std::size_t index = 0;
  std::vector<double> times;
  std::vector<double> obs;  // x0, y0, x1, y1, ...
  std::vector<double> model;
  RollState start;
};

/// Parameters: rho, sx, sy, then x, y, vx, vy, W per path.
constexpr int kGlobals = 3;
constexpr int kLocals = 5;

RollState local_state(const Eigen::VectorXd& p, std::size_t k) {
  const auto o = static_cast<Eigen::Index>(kGlobals + kLocals * k);
  return {p(o), p(o + 1), p(o + 2), p(o + 3), p(o + 4)};
}

/// Sum of squared data residuals [m^2] at parameters p (inf if a model run failed); fills each
/// path's model positions.
double data_cost(const field::Field& field, std::vector<FitPath>& paths, const Eigen::VectorXd& p) {
  if (!(p(0) > 0.0)) return kInf;
  const RollModel model(field, p(0), {p(1), p(2)});
  double sum = 0.0;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    FitPath& f = paths[k];
    if (!model.simulate(f.times.data(), f.times.size(), local_state(p, k), f.model.data()))
      return kInf;
    for (std::size_t i = 0; i < f.obs.size(); ++i) {
      const double r = f.model[i] - f.obs[i];
      sum += r * r;
    }
  }
  return std::isfinite(sum) ? sum : kInf;
}

/// Start values of (rho, sx, sy) by equation error: each path's acceleration, velocity and
/// position from quadratics over windows of its samples, set into the rigid point model (linear
/// in rho and the tilt at the lane's own slope), solved by least squares with the prior as
/// extra rows. Far cheaper than a path fit and close enough that the fit starts in the right
/// valley (a fit from the survey's rho can lock onto a ball that crests a hill the data's ball
/// did not). The prior's mean where the windows do not determine them.
std::array<double, 3> equation_error_start(const field::Field& field,
                                           const std::vector<FitPath>& paths,
                                           const std::array<double, 3>& mean,
                                           const std::array<double, 3>& std) {
  constexpr std::size_t kWindow = 15;
  constexpr double c57 = 5.0 / 7.0;
  const RollModel model(field, mean[0], {0.0, 0.0});
  std::vector<std::array<double, 4>> rows;  // coefficients of rho, sx, sy; right-hand side
  for (const FitPath& f : paths) {
    const std::size_t n = f.times.size();
    for (std::size_t lo = 0; lo + kWindow <= n; lo += kWindow / 2) {
      const std::size_t mid = lo + kWindow / 2;
      std::array<double, kWindow> t{};
      for (std::size_t i = 0; i < kWindow; ++i) t[i] = f.times[lo + i] - f.times[mid];
      double x, vx, ax, y, vy, ay;
      poly_fit3(t.data(), f.obs.data() + 2 * lo, kWindow, x, vx, ax);
      poly_fit3(t.data(), f.obs.data() + 2 * lo + 1, kWindow, y, vy, ay);
      RollModel::State st{x, y, vx, vy, 0.0, 0.0, 0.0};
      const auto l = model.local(st);
      const double q2 = l.q * l.q, sp = std::hypot(vx, vy);
      if (!(sp > 0.0)) continue;
      const double v3 = std::sqrt(sp * sp + std::pow(l.gx * vx + l.gy * vy, 2));
      const double push = (c57 * kSlopeFactor * kGravity + l.c) / q2;
      const double resist = c57 * kRollingResistanceFactor * (kGravity + l.c) / l.q / v3;
      rows.push_back({-resist * vx, -push, 0.0, ax + push * l.gx});
      rows.push_back({-resist * vy, 0.0, -push, ay + push * l.gy});
    }
  }
  if (rows.size() < 3) return mean;
  // Window accelerations are noisy: weigh the prior as if each row erred by 0.05 m/s^2.
  constexpr double kRowError = 0.05;
  const auto m = static_cast<Eigen::Index>(rows.size() + 3);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, 3);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    for (int j = 0; j < 3; ++j) a(r, j) = rows[i][static_cast<std::size_t>(j)] / kRowError;
    b(r) = rows[i][3] / kRowError;
  }
  for (int j = 0; j < 3; ++j) {
    const auto r = static_cast<Eigen::Index>(rows.size()) + j;
    const double w = std::isfinite(std[static_cast<std::size_t>(j)])
                         ? 1.0 / std[static_cast<std::size_t>(j)]
                         : 1e-6;  // an open direction stays at the prior's mean
    a(r, j) = w;
    b(r) = w * mean[static_cast<std::size_t>(j)];
  }
  const Eigen::Vector3d x = a.colPivHouseholderQr().solve(b);
  if (!(x(0) > 0.2 * mean[0] && x(0) < 5.0 * mean[0]) || !(std::abs(x(1)) < 0.1) ||
      !(std::abs(x(2)) < 0.1))
    return mean;
  return {x(0), x(1), x(2)};
}

}  // namespace

std::vector<std::array<double, 2>> predict_roll(const field::Field& surveyed,
                                                const GreenParams& green, const RollState& start,
                                                const std::vector<double>& times) {
  std::vector<std::array<double, 2>> out(times.size());
  if (times.empty()) return out;
  const RollModel model(surveyed, green.rolling_resistance, green.extra_slope);
  std::vector<double> xy(2 * times.size());
  if (!model.simulate(times.data(), times.size(), start, xy.data()))
    throw NumericalError("predict_roll: the rolling ball's state stopped being finite");
  for (std::size_t i = 0; i < times.size(); ++i) out[i] = {xy[2 * i], xy[2 * i + 1]};
  return out;
}

std::array<std::size_t, 2> rolling_span(const field::Field& field, const ObservedPath& path) {
  const auto& s = path.samples;
  const std::size_t n = s.size();
  if (n < 3) return {0, 0};
  // The slide: from the first samples' speed (a chord over the first 50 ms).
  std::size_t j = 1;
  while (j + 1 < n && s[j][0] - s[0][0] < 0.05) ++j;
  const double v0 = std::hypot(s[j][1] - s[0][1], s[j][2] - s[0][2]) / (s[j][0] - s[0][0]);
  const double slide = 2.0 * v0 / (7.0 * field.sliding_friction * kGravity);
  const double t_cut = s[0][0] + kSlideFactor * slide + kSlideMargin;
  std::size_t first = 0;
  while (first < n && s[first][0] < t_cut) ++first;
  const double r = field.ball.radius;
  const auto& b = field.bounds;
  const std::array<double, 2> hole = path.hole ? *path.hole : field.hole.position;
  const double hole_clear = 0.5 * field.hole.diameter + r + 0.01;
  std::size_t last = first;
  std::optional<ContactFilter> contact;
  double normal0 = 0.0, gravity0 = 0.0;
  for (; last < n; ++last) {
    const double x = s[last][1], y = s[last][2];
    const double border = std::min({x - b[0], b[1] - x, y - b[2], b[3] - y});
    if (border < r + 0.02) break;
    bool blocked = false;
    for (const auto& o : field.obstacles) blocked = blocked || o.distance({x, y}) < r + 0.02;
    if (blocked) break;
    if (std::hypot(x - hole[0], y - hole[1]) < hole_clear) break;
    double vx, vy;
    if (!velocity_at(s, last, vx, vy)) break;
    double normal, gravity;
    if (about_to_stop(field, x, y, vx, vy, normal, gravity)) break;
    if (!contact) {
      contact.emplace(normal);
    } else if (contact->advance(s[last][0] - s[last - 1][0], normal0, gravity0, normal, gravity) <
               kMinNormal * kGravity) {
      break;
    }
    const double sunk = -contact->e();
    if (std::hypot(vx, vy) * sunk / (2.0 * r - sunk) > kMaxSlip) break;
    normal0 = normal;
    gravity0 = gravity;
  }
  if (last < first + kMinSamples) return {first, first};
  return {first, last};
}

GreenEstimate fit_green(const field::Field& surveyed, const std::vector<ObservedPath>& paths,
                        const GreenPrior& prior, double vision_noise) {
  if (!(vision_noise >= 0.0) || !std::isfinite(vision_noise))
    throw InputError(
        fmt::format("fit_green: vision_noise: expected a finite std >= 0 m, got {}", vision_noise));
  for (int k = 0; k < 3; ++k)
    if (!(prior.std[k] > 0.0))
      throw InputError(fmt::format("fit_green: prior.std[{}]: expected > 0 (inf: no prior), got {}",
                                   k, prior.std[k]));
  if (!std::isfinite(prior.rolling_resistance) || !std::isfinite(prior.extra_slope[0]) ||
      !std::isfinite(prior.extra_slope[1]))
    throw InputError("fit_green: prior: expected finite values");
  GreenEstimate est;
  est.paths.resize(paths.size());
  std::vector<FitPath> fit;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    check_path(paths[k], k);
    const auto span = rolling_span(surveyed, paths[k]);
    PathFit& pf = est.paths[k];
    pf.first = span[0];
    pf.last = span[1];
    if (span[1] <= span[0]) continue;
    pf.used = true;
    FitPath f;
    f.index = k;
    const auto& s = paths[k].samples;
    const double t0 = s[span[0]][0];
    for (std::size_t i = span[0]; i < span[1]; ++i) {
      f.times.push_back(s[i][0]);
      f.obs.push_back(s[i][1]);
      f.obs.push_back(s[i][2]);
    }
    f.model.resize(f.obs.size());
    // The start: a quadratic through the first samples (at most 0.3 s of them).
    std::size_t m = 0;
    while (m < f.times.size() && f.times[m] - t0 <= 0.3) ++m;
    m = std::max<std::size_t>(m, std::min<std::size_t>(5, f.times.size()));
    std::vector<double> tr(m);
    for (std::size_t i = 0; i < m; ++i) tr[i] = f.times[i] - t0;
    poly_fit(tr.data(), f.obs.data(), m, 2, m >= 6, f.start.x, f.start.vx);
    poly_fit(tr.data(), f.obs.data() + 1, m, 2, m >= 6, f.start.y, f.start.vy);
    fit.push_back(std::move(f));
  }
  if (fit.empty())
    throw NumericalError(fmt::format(
        "fit_green: none of the {} paths has {} rolling samples (after the slide, before a "
        "border, an obstacle, the hole, a stop or a hop): nothing to identify the green from",
        paths.size(), kMinSamples));

  const auto np = static_cast<Eigen::Index>(kGlobals + kLocals * fit.size());
  Eigen::VectorXd p(np);
  p(0) = prior.rolling_resistance > 0.0 ? prior.rolling_resistance : surveyed.rolling_resistance;
  p(1) = prior.extra_slope[0];
  p(2) = prior.extra_slope[1];
  std::size_t nobs = 0;
  for (std::size_t k = 0; k < fit.size(); ++k) {
    const auto o = static_cast<Eigen::Index>(kGlobals + kLocals * k);
    p(o) = fit[k].start.x;
    p(o + 1) = fit[k].start.y;
    p(o + 2) = fit[k].start.vx;
    p(o + 3) = fit[k].start.vy;
    p(o + 4) = 0.0;
    nobs += fit[k].obs.size();
  }
  const std::array<double, 3> mean{p(0), p(1), p(2)};
  {
    const auto start = equation_error_start(surveyed, fit, mean, prior.std);
    for (int k = 0; k < 3; ++k) p(k) = start[static_cast<std::size_t>(k)];
  }
  const auto prior_cost = [&](const Eigen::VectorXd& q) {
    double c = 0.0;
    for (std::size_t k = 0; k < fit.size(); ++k) {
      const double z = q(static_cast<Eigen::Index>(kGlobals + kLocals * k + 4)) / kSpinPriorStd;
      c += z * z;
    }
    for (int k = 0; k < 3; ++k)
      if (std::isfinite(prior.std[k])) {
        const double z = (q(k) - mean[k]) / prior.std[k];
        c += z * z;
      }
    return c;
  };

  // Forward-difference steps of the parameters.
  constexpr double kStep = 1e-7;
  Eigen::MatrixXd jac_path;  // per path: rows 2 n, columns 7 (3 globals + 4 locals)
  Eigen::MatrixXd hess(np, np);
  Eigen::VectorXd grad(np);
  std::vector<double> base, bumped;
  std::vector<int> steps;

  // H = J'J / sigma^2 + prior, g = J'r / sigma^2 + prior; the data's J by forward differences.
  const auto linearise = [&](const Eigen::VectorXd& q, double sigma2) {
    hess.setZero();
    grad.setZero();
    for (std::size_t k = 0; k < fit.size(); ++k) {
      FitPath& f = fit[k];
      const std::size_t n = f.times.size();
      const auto rows = static_cast<Eigen::Index>(2 * n);
      jac_path.resize(rows, kGlobals + kLocals);
      base.resize(2 * n);
      bumped.resize(2 * n);
      const RollModel model(surveyed, q(0), {q(1), q(2)});
      const RollState start = local_state(q, k);
      // The bumped runs take the base run's steps: a difference quotient across a change of
      // steps would be noise.
      steps.resize(n);
      model.simulate(f.times.data(), n, start, base.data(), steps.data(), true);
      for (int c = 0; c < kGlobals + kLocals; ++c) {
        if (c < kGlobals) {
          std::array<double, 3> g{q(0), q(1), q(2)};
          g[static_cast<std::size_t>(c)] += kStep;
          const RollModel bumped_model(surveyed, g[0], {g[1], g[2]});
          bumped_model.simulate(f.times.data(), n, start, bumped.data(), steps.data(), false);
        } else {
          RollState s = start;
          (c == 3 ? s.x : c == 4 ? s.y : c == 5 ? s.vx : c == 6 ? s.vy : s.spin) += kStep;
          model.simulate(f.times.data(), n, s, bumped.data(), steps.data(), false);
        }
        for (Eigen::Index r = 0; r < rows; ++r)
          jac_path(r, c) =
              (bumped[static_cast<std::size_t>(r)] - base[static_cast<std::size_t>(r)]) / kStep;
      }
      Eigen::VectorXd res(rows);
      for (Eigen::Index r = 0; r < rows; ++r)
        res(r) = base[static_cast<std::size_t>(r)] - f.obs[static_cast<std::size_t>(r)];
      const Eigen::MatrixXd jtj = jac_path.transpose() * jac_path / sigma2;
      const Eigen::VectorXd jtr = jac_path.transpose() * res / sigma2;
      const auto o = static_cast<Eigen::Index>(kGlobals + kLocals * k);
      hess.topLeftCorner(kGlobals, kGlobals) += jtj.topLeftCorner(kGlobals, kGlobals);
      hess.block(0, o, kGlobals, kLocals) += jtj.topRightCorner(kGlobals, kLocals);
      hess.block(o, 0, kLocals, kGlobals) += jtj.bottomLeftCorner(kLocals, kGlobals);
      hess.block(o, o, kLocals, kLocals) += jtj.bottomRightCorner(kLocals, kLocals);
      grad.head(kGlobals) += jtr.head(kGlobals);
      grad.segment(o, kLocals) += jtr.tail(kLocals);
      const double w = 1.0 / (kSpinPriorStd * kSpinPriorStd);
      hess(o + 4, o + 4) += w;
      grad(o + 4) += w * q(o + 4);
    }
    for (int k = 0; k < 3; ++k)
      if (std::isfinite(prior.std[k])) {
        const double w = 1.0 / (prior.std[k] * prior.std[k]);
        hess(k, k) += w;
        grad(k) += w * (q(k) - mean[k]);
      }
  };

  // Levenberg-Marquardt on cost = data / sigma^2 + prior.
  double sigma = vision_noise > 0.0 ? vision_noise : 1e-3;
  const auto solve = [&](Eigen::VectorXd& q, double sigma2) {
    double data = data_cost(surveyed, fit, q);
    if (!std::isfinite(data))
      throw NumericalError("fit_green: the model ball's state is not finite at the start values");
    double cost = data / sigma2 + prior_cost(q);
    double lambda = 1e-3;
    linearise(q, sigma2);
    for (int it = 0; it < 100; ++it) {
      Eigen::MatrixXd a = hess;
      for (Eigen::Index i = 0; i < np; ++i) a(i, i) += lambda * std::max(hess(i, i), 1e-12);
      const Eigen::VectorXd step = a.ldlt().solve(-grad);
      const Eigen::VectorXd trial = q + step;
      const double trial_data = data_cost(surveyed, fit, trial);
      const double trial_cost = trial_data / sigma2 + prior_cost(trial);
      if (std::isfinite(trial_cost) && trial_cost < cost) {
        const double gain = cost - trial_cost;
        q = trial;
        cost = trial_cost;
        data = trial_data;
        ++est.iterations;
        lambda = std::max(lambda * 0.1, 1e-12);
        // A gain under 1e-3 in chi-square is no gain the data can tell from zero.
        if (gain < 1e-3) break;
        linearise(q, sigma2);
      } else {
        lambda *= 10.0;
        if (lambda > 1e12) break;
      }
    }
    return data;
  };
  double data = solve(p, sigma * sigma);
  const auto dof = static_cast<double>(std::max<std::ptrdiff_t>(
      1, static_cast<std::ptrdiff_t>(nobs) - static_cast<std::ptrdiff_t>(np)));
  if (vision_noise == 0.0) {
    // The vision's error from the residuals: the fit's balance with the priors depends on it.
    for (int round = 0; round < 3; ++round) {
      const double next = std::max(std::sqrt(data / dof), 1e-9);
      const bool settled = std::abs(next - sigma) <= 0.05 * sigma;
      sigma = next;
      if (settled) break;
      data = solve(p, sigma * sigma);
    }
    sigma = std::max(std::sqrt(data / dof), 1e-9);
  }
  linearise(p, sigma * sigma);

  // The globals' covariance: the Schur complement of the locals in the Gauss-Newton Hessian.
  Eigen::MatrixXd s = hess.topLeftCorner(kGlobals, kGlobals);
  for (std::size_t k = 0; k < fit.size(); ++k) {
    const auto o = static_cast<Eigen::Index>(kGlobals + kLocals * k);
    const Eigen::MatrixXd b = hess.block(0, o, kGlobals, kLocals);
    const Eigen::MatrixXd c = hess.block(o, o, kLocals, kLocals);
    s -= b * c.ldlt().solve(b.transpose());
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s);
  const double top = eig.eigenvalues().cwiseAbs().maxCoeff();
  const auto open_direction = [&](int j) {
    const double v = eig.eigenvalues()(j);
    return !(v > 1e-12 * top && v > 0.0);
  };
  Eigen::VectorXd inv_values(kGlobals);
  for (int j = 0; j < kGlobals; ++j)
    inv_values(j) = open_direction(j) ? 0.0 : 1.0 / eig.eigenvalues()(j);
  const Eigen::MatrixXd cov =
      eig.eigenvectors() * inv_values.asDiagonal() * eig.eigenvectors().transpose();
  for (int i = 0; i < kGlobals; ++i) {
    // A direction the data and prior leave open makes every parameter it touches unknown.
    bool open = false;
    for (int j = 0; j < kGlobals; ++j)
      open = open || (open_direction(j) && std::abs(eig.eigenvectors()(i, j)) > 1e-6);
    est.std[static_cast<std::size_t>(i)] = open ? kInf : std::sqrt(std::max(cov(i, i), 0.0));
  }

  est.rolling_resistance = p(0);
  est.extra_slope = {p(1), p(2)};
  est.paths_used = static_cast<int>(fit.size());
  est.samples_used = static_cast<int>(nobs / 2);
  data_cost(surveyed, fit, p);
  double total = 0.0;
  for (std::size_t k = 0; k < fit.size(); ++k) {
    const FitPath& f = fit[k];
    double sum = 0.0;
    for (std::size_t i = 0; i < f.obs.size(); ++i)
      sum += (f.model[i] - f.obs[i]) * (f.model[i] - f.obs[i]);
    total += sum;
    PathFit& pf = est.paths[f.index];
    pf.start = local_state(p, k);
    pf.rms_residual = std::sqrt(sum / static_cast<double>(f.obs.size()));
  }
  est.rms_residual = std::sqrt(total / static_cast<double>(nobs));
  return est;
}

}  // namespace mg::belief
