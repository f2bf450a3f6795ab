#include "belief/path_fit.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "belief/roll_model.hpp"
#include "core/error.hpp"

namespace mg::belief {
namespace {

using namespace detail;  // the rolling model and its constants (roll_model.hpp)

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

/// Appends the residuals of run `run` of a fitted path (its model positions filled), each with
/// the model's direction of motion there (from its neighbouring model positions).
void append_residuals(const FitPath& f, int run, std::vector<SampleResidual>& out) {
  const std::size_t n = f.times.size();
  for (std::size_t i = 0; i < n; ++i) {
    SampleResidual r;
    r.path = static_cast<int>(f.index);
    r.run = run;
    r.t = f.times[i];
    r.x = f.obs[2 * i];
    r.y = f.obs[2 * i + 1];
    r.dx = f.obs[2 * i] - f.model[2 * i];
    r.dy = f.obs[2 * i + 1] - f.model[2 * i + 1];
    const std::size_t a = i > 0 ? i - 1 : 0, b = i + 1 < n ? i + 1 : i;
    const double hx = f.model[2 * b] - f.model[2 * a], hy = f.model[2 * b + 1] - f.model[2 * a + 1];
    const double norm = std::hypot(hx, hy);
    if (norm > 0.0) r.heading = {hx / norm, hy / norm};
    out.push_back(r);
  }
}

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

GreenEstimate fit_green(const field::Field& surveyed, const std::vector<ObservedPath>& paths,
                        const GreenPrior& prior, double vision_noise, bool every_run) {
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
    std::vector<std::array<std::size_t, 2>> spans;
    if (every_run) {
      spans = rolling_spans(surveyed, paths[k]);
    } else if (const auto span = rolling_span(surveyed, paths[k]); span[1] > span[0]) {
      spans.push_back(span);
    }
    PathFit& pf = est.paths[k];
    if (spans.empty()) {
      pf.first = pf.last = rolling_span(surveyed, paths[k])[0];
      continue;
    }
    pf.first = spans.front()[0];
    pf.last = spans.front()[1];
    pf.used = true;
    // Each run its own start state: the crest between two runs is not modelled.
    for (const auto& span : spans) {
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
  est.paths_used = 0;
  for (const PathFit& pf : est.paths) est.paths_used += pf.used ? 1 : 0;
  est.samples_used = static_cast<int>(nobs / 2);
  data_cost(surveyed, fit, p);
  double total = 0.0;
  int run = 0;
  for (std::size_t k = 0; k < fit.size(); ++k) {
    const FitPath& f = fit[k];
    double sum = 0.0;
    for (std::size_t i = 0; i < f.obs.size(); ++i)
      sum += (f.model[i] - f.obs[i]) * (f.model[i] - f.obs[i]);
    total += sum;
    run = k > 0 && fit[k - 1].index == f.index ? run + 1 : 0;
    append_residuals(f, run, est.residuals);
    if (run > 0) continue;  // a later run of the same path
    PathFit& pf = est.paths[f.index];
    pf.start = local_state(p, k);
    pf.rms_residual = std::sqrt(sum / static_cast<double>(f.obs.size()));
  }
  est.rms_residual = std::sqrt(total / static_cast<double>(nobs));
  return est;
}

}  // namespace mg::belief
