// Fitting SEDS: the initial guess (a GMM of the demonstrations, its A's projected to stable
// ones) and the constrained optimisation (NLopt: the objective of seds.cpp with its gradient,
// one stability constraint per Gaussian), then dropping Gaussians left without data.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <nlopt.hpp>

#include "core/error.hpp"
#include "ds/seds.hpp"
#include "ds/seds_layout.hpp"
#include "stats/gmm.hpp"

namespace mg::ds {

using namespace seds_layout;
using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

std::vector<SedsComponent> seds_initial_guess(const SedsData& data, const SedsOptions& options) {
  options.validate();
  const auto n = data.size();
  if (n < options.gaussians)
    throw InputError(fmt::format(
        "SEDS: expected at least as many samples as Gaussians ({}), got {}", options.gaussians, n));
  Eigen::MatrixXd joint(n, 6);
  joint.leftCols<3>() = data.y.transpose();
  joint.rightCols<3>() = data.ydot.transpose();
  Rng rng(options.seed);
  stats::EmOptions em;
  em.reg_covar = options.covariance_floor;
  const auto fit = stats::fit_gmm(joint, options.gaussians, rng, em);
  auto comps = seds_from_gmm(fit.gmm);
  // Make feasible: project A_k onto {lambda(A + A^T) <= -2 delta} keeping its skew part.
  const double delta = 2.0 * options.optimizer_margin;
  for (auto& c : comps) {
    const Mat3 sym = 0.5 * (c.a + c.a.transpose());
    const Mat3 skew = 0.5 * (c.a - c.a.transpose());
    Eigen::SelfAdjointEigenSolver<Mat3> eig(sym);
    const Vec3 ev = eig.eigenvalues().cwiseMin(-delta);
    c.a = eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose() + skew;
    // Inside the optimiser's box (|A_ij| <= max_rate): a positive scale keeps A + A^T negative
    // definite; re-projecting adds at most 2 delta to the diagonal.
    const double biggest = c.a.cwiseAbs().maxCoeff();
    if (options.max_rate > 0.0 && biggest > 0.5 * options.max_rate) {
      c.a *= 0.5 * options.max_rate / biggest;
      const Mat3 s2 = 0.5 * (c.a + c.a.transpose());
      Eigen::SelfAdjointEigenSolver<Mat3> e2(s2);
      c.a = e2.eigenvectors() * e2.eigenvalues().cwiseMin(-delta).asDiagonal() *
                e2.eigenvectors().transpose() +
            0.5 * (c.a - c.a.transpose());
    }
    c.prior = std::max(c.prior, 1e-6);
    // Velocity covariance consistent with the projected A (responsibility-weighted residuals).
    c.c = 0.5 * (c.c + c.c.transpose()).eval();
    Eigen::SelfAdjointEigenSolver<Mat3> ec(c.c);
    if (ec.eigenvalues().minCoeff() < options.covariance_floor)
      c.c = ec.eigenvectors() *
            ec.eigenvalues().cwiseMax(10 * options.covariance_floor).asDiagonal() *
            ec.eigenvectors().transpose();
  }
  double total = 0.0;
  for (const auto& c : comps) total += c.prior;
  for (auto& c : comps) c.prior /= total;
  return comps;
}

namespace {

struct OptContext {
  const SedsData* data = nullptr;
  const SedsOptions* options = nullptr;
  const std::vector<SedsComponent>* templ = nullptr;
  int evaluations = 0;
  double best_value = std::numeric_limits<double>::infinity();
  std::vector<double> best_x;
};

double max_constraint(const std::vector<double>& x, int kc, int b) {
  double worst = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < kc; ++k)
    worst = std::max(worst, stability_eigenvalue(Eigen::Map<const Mat3>(x.data() + k * b + kA)));
  return worst;
}

double nlopt_objective(const std::vector<double>& x, std::vector<double>& grad, void* raw) {
  auto* ctx = static_cast<OptContext*>(raw);
  ++ctx->evaluations;
  if (ctx->options->on_evaluation) ctx->options->on_evaluation(ctx->evaluations);
  const Eigen::Map<const Eigen::VectorXd> p(x.data(), static_cast<Eigen::Index>(x.size()));
  Eigen::VectorXd g;
  const double v =
      seds_objective(p, *ctx->data, ctx->options->objective, ctx->options->covariance_floor,
                     *ctx->templ, grad.empty() ? nullptr : &g);
  if (!grad.empty())
    Eigen::Map<Eigen::VectorXd>(grad.data(), static_cast<Eigen::Index>(grad.size())) = g;
  const int b = block_size(ctx->options->objective);
  // Remember the best point that satisfies the REQUIRED margin: the answer if SLSQP ends
  // infeasible.
  if (std::isfinite(v) && v < ctx->best_value &&
      max_constraint(x, static_cast<int>(x.size()) / b, b) <= -ctx->options->margin) {
    ctx->best_value = v;
    ctx->best_x = x;
  }
  return std::isfinite(v) ? v : 1e300;
}

void nlopt_constraints(unsigned m, double* result, unsigned n, const double* x, double* grad,
                       void* raw) {
  const auto* ctx = static_cast<const OptContext*>(raw);
  const int b = block_size(ctx->options->objective);
  if (grad) std::fill(grad, grad + static_cast<std::size_t>(m) * n, 0.0);
  for (unsigned k = 0; k < m; ++k) {
    const Eigen::Map<const Mat3> a(x + k * b + kA);
    Eigen::SelfAdjointEigenSolver<Mat3> eig(a + a.transpose());
    result[k] = eig.eigenvalues()[2] + ctx->options->optimizer_margin;
    if (grad) {
      // d lambda_max / d A_ij = 2 v_i v_j (simple eigenvalue); A is stored column-major.
      const Vec3 v = eig.eigenvectors().col(2);
      const Mat3 d = 2.0 * v * v.transpose();
      for (int j = 0; j < 9; ++j) grad[k * n + k * b + kA + j] = d.data()[j];
    }
  }
}

std::string nlopt_status_name(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS:
      return "success";
    case nlopt::STOPVAL_REACHED:
      return "stopval reached";
    case nlopt::FTOL_REACHED:
      return "ftol reached";
    case nlopt::XTOL_REACHED:
      return "xtol reached";
    case nlopt::MAXEVAL_REACHED:
      return "maxeval reached";
    case nlopt::MAXTIME_REACHED:
      return "maxtime reached";
    default:
      return fmt::format("nlopt result {}", static_cast<int>(r));
  }
}

}  // namespace

void drop_empty_components(SedsResult& result, double min_prior) {
  if (result.components.size() > 1) {
    std::vector<SedsComponent> kept;
    for (std::size_t k = 0; k < result.components.size(); ++k) {
      if (result.components[k].prior >= min_prior) {
        kept.push_back(result.components[k]);
      } else {
        result.notes.push_back(
            fmt::format("dropped SEDS component {} of {} (prior {:.2g} < {:g}: no data left in it)",
                        k, result.components.size(), result.components[k].prior, min_prior));
      }
    }
    if (kept.empty()) {
      kept.push_back(
          *std::max_element(result.components.begin(), result.components.end(),
                            [](const auto& a, const auto& b) { return a.prior < b.prior; }));
      result.notes.clear();
    }
    if (kept.size() < result.components.size()) {
      double total = 0.0;
      for (const auto& c : kept) total += c.prior;
      for (auto& c : kept) c.prior /= total;
      result.components = std::move(kept);
    }
  }
}

SedsResult fit_seds(const SedsData& data, const SedsOptions& options) {
  options.validate();
  if (!data.y.allFinite() || !data.ydot.allFinite())
    throw InputError("SEDS data: expected finite samples");
  const auto init = seds_initial_guess(data, options);
  const Eigen::VectorXd p0 = pack_seds(init, options.objective, options.covariance_floor);
  const int b = block_size(options.objective);

  OptContext ctx;
  ctx.data = &data;
  ctx.options = &options;
  ctx.templ = &init;
  SedsResult result;
  result.initial_objective =
      seds_objective(p0, data, options.objective, options.covariance_floor, init, nullptr);

  nlopt::opt opt(nlopt::LD_SLSQP, static_cast<unsigned>(p0.size()));
  opt.set_min_objective(nlopt_objective, &ctx);
  opt.add_inequality_mconstraint(
      nlopt_constraints, &ctx,
      std::vector<double>(static_cast<std::size_t>(options.gaussians), 1e-9));
  if (options.max_rate > 0.0) {
    std::vector<double> lower(p0.size(), -HUGE_VAL), upper(p0.size(), HUGE_VAL);
    for (int k = 0; k < options.gaussians; ++k)
      for (int j = 0; j < 9; ++j) {
        lower[static_cast<std::size_t>(k * b + kA + j)] = -options.max_rate;
        upper[static_cast<std::size_t>(k * b + kA + j)] = options.max_rate;
      }
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
  }
  opt.set_ftol_rel(options.relative_tolerance);
  opt.set_maxeval(options.max_evaluations);
  std::vector<double> x(p0.data(), p0.data() + p0.size());
  double fx = 0.0;
  try {
    const auto status = opt.optimize(x, fx);
    result.optimizer_status = nlopt_status_name(status);
  } catch (const std::exception& e) {
    // Round-off and similar stops: keep the best feasible point seen.
    result.optimizer_status = fmt::format("nlopt stopped early ({})", e.what());
  }
  result.evaluations = ctx.evaluations;
  const bool final_ok =
      max_constraint(x, options.gaussians, b) <= -options.margin && std::isfinite(fx);
  if (!final_ok || (ctx.best_x.size() == x.size() && ctx.best_value < fx)) {
    if (ctx.best_x.empty()) {
      x.assign(p0.data(), p0.data() + p0.size());  // the projected start is feasible
      result.optimizer_status += "; kept the feasible start";
    } else {
      x = ctx.best_x;
      result.optimizer_status += "; kept the best feasible point";
    }
  }
  const Eigen::Map<const Eigen::VectorXd> p(x.data(), static_cast<Eigen::Index>(x.size()));
  result.final_objective =
      seds_objective(p, data, options.objective, options.covariance_floor, init, nullptr);
  result.components = unpack_seds(p, options.objective, options.covariance_floor, init);

  if (options.objective == SedsObjective::kMse) {
    // The MSE objective leaves the velocity covariance free: estimate it from the weighted
    // residuals.
    for (auto& c : result.components) c.c.setZero();
    std::vector<double> weight(result.components.size(), 0.0);
    for (Eigen::Index i = 0; i < data.size(); ++i) {
      const Vec3 y = data.y.col(i);
      Eigen::VectorXd logit(static_cast<Eigen::Index>(result.components.size()));
      for (std::size_t k = 0; k < result.components.size(); ++k) {
        const auto& c = result.components[k];
        const Eigen::LLT<Mat3> llt(c.sigma);
        const Vec3 w = llt.matrixL().solve(y - c.mu);
        logit[static_cast<Eigen::Index>(k)] =
            std::log(c.prior) -
            0.5 * (2.0 * llt.matrixLLT().diagonal().array().log().sum() + w.squaredNorm());
      }
      const Eigen::VectorXd h = (logit.array() - log_sum_exp(logit)).exp();
      for (std::size_t k = 0; k < result.components.size(); ++k) {
        const Vec3 u = data.ydot.col(i) - result.components[k].a * y;
        result.components[k].c += h[static_cast<Eigen::Index>(k)] * u * u.transpose();
        weight[k] += h[static_cast<Eigen::Index>(k)];
      }
    }
    for (std::size_t k = 0; k < result.components.size(); ++k) {
      auto& c = result.components[k];
      c.c /= std::max(weight[k], 1e-12);
      c.c.diagonal().array() += std::max(options.covariance_floor, 1e-4);
    }
  }

  result.max_eigenvalue = -std::numeric_limits<double>::infinity();
  for (const auto& c : result.components)
    result.max_eigenvalue = std::max(result.max_eigenvalue, stability_eigenvalue(c.a));
  if (!(result.max_eigenvalue <= -options.margin))
    throw NumericalError(
        fmt::format("SEDS fit: expected lambda_max(A_k + A_k^T) <= {} for every component, got {}",
                    -options.margin, result.max_eigenvalue));
  return result;
}

}  // namespace mg::ds
