#include "stats/gpr.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <nlopt.hpp>

#include "core/error.hpp"
#include "stats/linalg.hpp"

namespace mg::stats {
namespace {

constexpr double kLog2Pi = 1.8378770664093453;  // log(2 pi)

// Per-dimension squared differences (a_i - b_i)^2 of all training pairs, computed once per fit.
std::vector<Eigen::MatrixXd> pairwise_sq_diffs(const Eigen::MatrixXd& x) {
  std::vector<Eigen::MatrixXd> d2;
  const Eigen::Index n = x.rows();
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    const Eigen::VectorXd c = x.col(i);
    Eigen::MatrixXd m(n, n);
    for (Eigen::Index a = 0; a < n; ++a)
      for (Eigen::Index b = 0; b < n; ++b) m(a, b) = (c(a) - c(b)) * (c(a) - c(b));
    d2.push_back(std::move(m));
  }
  return d2;
}

Eigen::MatrixXd kernel_matrix(const std::vector<Eigen::MatrixXd>& d2, Eigen::Index n,
                              const Eigen::VectorXd& log_params) {
  const auto d = static_cast<Eigen::Index>(d2.size());
  Eigen::MatrixXd scaled = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < d; ++i)
    scaled += d2[static_cast<std::size_t>(i)] * std::exp(-2.0 * log_params(i));
  const double sf2 = std::exp(2.0 * log_params(d));
  return sf2 * (-0.5 * scaled.array()).exp().matrix();
}

double lml_impl(const std::vector<Eigen::MatrixXd>& d2, const Eigen::VectorXd& y,
                const Eigen::VectorXd& log_params, Eigen::VectorXd* gradient) {
  const Eigen::Index n = y.size();
  const auto d = static_cast<Eigen::Index>(d2.size());
  const Eigen::MatrixXd k = kernel_matrix(d2, n, log_params);
  const double sn2 = std::exp(2.0 * log_params(d + 1));
  Eigen::MatrixXd ky = k;
  ky.diagonal().array() += sn2;
  const Eigen::LLT<Eigen::MatrixXd> llt(ky);
  if (llt.info() != Eigen::Success) {
    if (gradient) gradient->setZero(d + 2);
    return -std::numeric_limits<double>::infinity();
  }
  const Eigen::VectorXd alpha = llt.solve(y);
  const Eigen::MatrixXd l = llt.matrixL();
  const double lml = -0.5 * y.dot(alpha) - l.diagonal().array().log().sum() -
                     0.5 * static_cast<double>(n) * kLog2Pi;
  if (gradient) {
    // d lml / d theta = 1/2 tr((alpha alpha^T - Ky^-1) dKy/dtheta)   (GPML eq. 5.9)
    Eigen::MatrixXd w = alpha * alpha.transpose() - llt.solve(Eigen::MatrixXd::Identity(n, n));
    const Eigen::MatrixXd wk = w.cwiseProduct(k);
    gradient->resize(d + 2);
    for (Eigen::Index i = 0; i < d; ++i)
      (*gradient)(i) = 0.5 * wk.cwiseProduct(d2[static_cast<std::size_t>(i)]).sum() *
                       std::exp(-2.0 * log_params(i));
    (*gradient)(d) = wk.sum();
    (*gradient)(d + 1) = sn2 * w.trace();
  }
  return std::isfinite(lml) ? lml : -std::numeric_limits<double>::infinity();
}

double column_std(const Eigen::VectorXd& c) {
  if (c.size() < 2) return 0.0;
  const double m = c.mean();
  return std::sqrt((c.array() - m).square().mean());
}

void require_training_data(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& targets) {
  if (inputs.rows() < 1 || inputs.cols() < 1)
    throw InputError(
        fmt::format("GPR: training inputs: expected N >= 1 rows and D >= 1 columns, got {} x {}",
                    inputs.rows(), inputs.cols()));
  if (targets.size() != inputs.rows())
    throw InputError(
        fmt::format("GPR: training targets: expected {} values (one per input row), got {}",
                    inputs.rows(), targets.size()));
  if (!inputs.allFinite() || !targets.allFinite())
    throw InputError("GPR: training data: expected finite values, got NaN or inf");
  // Squared differences and variances of values beyond 1e100 overflow: predictions would be NaN.
  constexpr double kMaxValue = 1e100;
  for (Eigen::Index i = 0; i < inputs.rows(); ++i) {
    for (Eigen::Index j = 0; j < inputs.cols(); ++j)
      if (std::abs(inputs(i, j)) > kMaxValue)
        throw InputError(fmt::format("GPR: training input row {}, column {}: {:g} is beyond +-{:g}",
                                     i, j, inputs(i, j), kMaxValue));
    if (std::abs(targets(i)) > kMaxValue)
      throw InputError(
          fmt::format("GPR: training target {}: {:g} is beyond +-{:g}", i, targets(i), kMaxValue));
  }
}

struct OptContext {
  const std::vector<Eigen::MatrixXd>* d2 = nullptr;
  const Eigen::VectorXd* y = nullptr;
  Eigen::VectorXd best_x;
  double best_value = -std::numeric_limits<double>::infinity();
};

double nlopt_objective(unsigned n, const double* x, double* grad, void* data) {
  auto* ctx = static_cast<OptContext*>(data);
  const Eigen::Map<const Eigen::VectorXd> p(x, n);
  Eigen::VectorXd g;
  const double v = lml_impl(*ctx->d2, *ctx->y, p, grad ? &g : nullptr);
  if (!std::isfinite(v)) {
    if (grad) std::fill(grad, grad + n, 0.0);
    return -1e300;
  }
  if (grad) std::copy(g.data(), g.data() + n, grad);
  if (v > ctx->best_value) {
    ctx->best_value = v;
    ctx->best_x = p;
  }
  return v;
}

double uniform01(mg::Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

void check_bounds(const char* name, const std::array<double, 2>& b) {
  if (b[0] == 0.0 && b[1] == 0.0) return;
  if (!(b[0] > 0.0) || !(b[1] >= b[0]) || !std::isfinite(b[1]))
    throw InputError(fmt::format("GPR options: {}: expected 0 < lower <= upper, got [{}, {}]", name,
                                 b[0], b[1]));
}

}  // namespace

void GprOptions::validate() const {
  if (restarts < 1)
    throw InputError(fmt::format("GPR options: restarts: expected >= 1, got {}", restarts));
  if (max_evaluations < 1)
    throw InputError(
        fmt::format("GPR options: max_evaluations: expected >= 1, got {}", max_evaluations));
  for (Eigen::Index i = 0; i < initial_length_scales.size(); ++i)
    if (!(initial_length_scales(i) > 0.0) || !std::isfinite(initial_length_scales(i)))
      throw InputError(
          fmt::format("GPR options: initial length scale {}: expected a positive number, got {}", i,
                      initial_length_scales(i)));
  if (!(initial_signal_std >= 0.0) || !std::isfinite(initial_signal_std))
    throw InputError(fmt::format(
        "GPR options: initial signal std: expected a positive number, got {}", initial_signal_std));
  if (!(initial_noise_std >= 0.0) || !std::isfinite(initial_noise_std))
    throw InputError(fmt::format(
        "GPR options: initial noise std: expected a positive number, got {}", initial_noise_std));
  check_bounds("length scale bounds", length_scale_bounds);
  check_bounds("signal std bounds", signal_std_bounds);
  check_bounds("noise std bounds", noise_std_bounds);
}

double gp_log_marginal_likelihood(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& y,
                                  const Eigen::VectorXd& log_params, Eigen::VectorXd* gradient) {
  require_training_data(inputs, y);
  if (log_params.size() != inputs.cols() + 2)
    throw InputError(
        fmt::format("GPR: log parameters: expected {} values (D length scales, sf, sn), got {}",
                    inputs.cols() + 2, log_params.size()));
  return lml_impl(pairwise_sq_diffs(inputs), y, log_params, gradient);
}

GpModel make_gp_model(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& targets,
                      const GpHyperparameters& hyper) {
  require_training_data(inputs, targets);
  const Eigen::Index n = inputs.rows();
  const Eigen::Index d = inputs.cols();
  if (hyper.length_scales.size() != d)
    throw InputError(fmt::format("GPR: length scales: expected {} values (one per input), got {}",
                                 d, hyper.length_scales.size()));
  for (Eigen::Index i = 0; i < d; ++i)
    if (!(hyper.length_scales(i) > 0.0) || !std::isfinite(hyper.length_scales(i)))
      throw InputError(fmt::format("GPR: length scale {}: expected a positive number, got {}", i,
                                   hyper.length_scales(i)));
  if (!(hyper.signal_std > 0.0) || !(hyper.signal_std <= 1e100))
    throw InputError(fmt::format("GPR: signal std: expected a positive number <= 1e100, got {}",
                                 hyper.signal_std));
  if (!(hyper.noise_std >= 0.0) || !(hyper.noise_std <= 1e100))
    throw InputError(
        fmt::format("GPR: noise std: expected a number in [0, 1e100], got {}", hyper.noise_std));

  GpModel m;
  m.inputs = inputs;
  m.targets = targets;
  m.hyper = hyper;
  m.output_mean = targets.mean();
  const double s = column_std(targets);
  m.output_scale = s > 0.0 ? s : 1.0;
  const Eigen::VectorXd y = (targets.array() - m.output_mean) / m.output_scale;

  Eigen::VectorXd log_params(d + 2);
  log_params.head(d) = hyper.length_scales.array().log();
  log_params(d) = std::log(hyper.signal_std / m.output_scale);
  log_params(d + 1) = std::log(std::max(hyper.noise_std / m.output_scale, 1e-300));
  Eigen::MatrixXd ky = kernel_matrix(pairwise_sq_diffs(inputs), n, log_params);
  const double sn_s = hyper.noise_std / m.output_scale;
  ky.diagonal().array() += sn_s * sn_s;
  m.chol = robust_cholesky(ky, &m.jitter);
  m.alpha = m.chol.triangularView<Eigen::Lower>().solve(y);
  m.chol.transpose().triangularView<Eigen::Upper>().solveInPlace(m.alpha);
  m.log_marginal_likelihood = -0.5 * y.dot(m.alpha) - m.chol.diagonal().array().log().sum() -
                              0.5 * static_cast<double>(n) * kLog2Pi -
                              static_cast<double>(n) * std::log(m.output_scale);
  return m;
}

GpModel fit_gpr(const Eigen::MatrixXd& inputs, const Eigen::VectorXd& targets, mg::Rng& rng,
                const GprOptions& options) {
  options.validate();
  require_training_data(inputs, targets);
  const Eigen::Index d = inputs.cols();
  if (options.initial_length_scales.size() != 0 && options.initial_length_scales.size() != 1 &&
      options.initial_length_scales.size() != d)
    throw InputError(
        fmt::format("GPR options: initial length scales: expected 1 or {} values, got {}", d,
                    options.initial_length_scales.size()));
  const double y_std = column_std(targets);
  const double y_scale = y_std > 0.0 ? y_std : 1.0;

  // Initial guess and bounds in log space, standardised output units.
  const Eigen::Index p = d + 2;
  Eigen::VectorXd x0(p), lo(p), hi(p);
  for (Eigen::Index i = 0; i < d; ++i) {
    double s = column_std(inputs.col(i));
    if (!(s > 0.0)) s = 1.0;
    const bool user_bounds = options.length_scale_bounds[1] > 0.0;
    lo(i) = std::log(user_bounds ? options.length_scale_bounds[0] : 1e-2 * s);
    hi(i) = std::log(user_bounds ? options.length_scale_bounds[1] : 1e2 * s);
    const double init = options.initial_length_scales.size() == 0 ? s
                        : options.initial_length_scales.size() == 1
                            ? options.initial_length_scales(0)
                            : options.initial_length_scales(i);
    x0(i) = std::log(init);
  }
  auto set = [&](Eigen::Index i, const std::array<double, 2>& b, double dlo, double dhi,
                 double init, double dinit) {
    const bool user_bounds = b[1] > 0.0;
    lo(i) = std::log(user_bounds ? b[0] / y_scale : dlo);
    hi(i) = std::log(user_bounds ? b[1] / y_scale : dhi);
    x0(i) = std::log(init > 0.0 ? init / y_scale : dinit);
  };
  set(d, options.signal_std_bounds, 1e-2, 1e2, options.initial_signal_std, 1.0);
  set(d + 1, options.noise_std_bounds, 1e-3, 2.0, options.initial_noise_std, 0.1);
  x0 = x0.cwiseMax(lo).cwiseMin(hi);

  Eigen::VectorXd best = x0;
  if (options.optimize) {
    const std::vector<Eigen::MatrixXd> d2 = pairwise_sq_diffs(inputs);
    const double m = targets.mean();
    const Eigen::VectorXd y = (targets.array() - m) / y_scale;
    OptContext ctx;
    ctx.d2 = &d2;
    ctx.y = &y;
    nlopt::opt opt(nlopt::LD_LBFGS, static_cast<unsigned>(p));
    opt.set_lower_bounds(std::vector<double>(lo.data(), lo.data() + p));
    opt.set_upper_bounds(std::vector<double>(hi.data(), hi.data() + p));
    opt.set_max_objective(nlopt_objective, &ctx);
    opt.set_ftol_rel(1e-12);
    opt.set_xtol_rel(1e-8);
    opt.set_maxeval(options.max_evaluations);
    for (int r = 0; r < options.restarts; ++r) {
      Eigen::VectorXd start = x0;
      if (r > 0)
        for (Eigen::Index i = 0; i < p; ++i) start(i) = lo(i) + uniform01(rng) * (hi(i) - lo(i));
      std::vector<double> xv(start.data(), start.data() + p);
      double value = 0.0;
      try {
        opt.optimize(xv, value);
      } catch (const std::exception&) {
        // Round-off limited or failed line search: the best point seen so far is kept in ctx.
      }
    }
    if (ctx.best_x.size() == p) best = ctx.best_x;
  }

  GpHyperparameters hyper;
  hyper.length_scales = best.head(d).array().exp();
  hyper.signal_std = std::exp(best(d)) * y_scale;
  hyper.noise_std = std::exp(best(d + 1)) * y_scale;
  return make_gp_model(inputs, targets, hyper);
}

GpWorkspace make_gp_workspace(const GpModel& model) {
  GpWorkspace ws;
  ws.k_star.resize(model.size());
  ws.diff.resize(model.dim());
  return ws;
}

GpPrediction gp_predict(const GpModel& model, const Eigen::Ref<const Eigen::VectorXd>& x,
                        GpWorkspace& ws) {
  const double sf_s = model.hyper.signal_std / model.output_scale;
  const double sf2 = sf_s * sf_s;
  for (int a = 0; a < model.size(); ++a) {
    ws.diff = (model.inputs.row(a).transpose() - x).cwiseQuotient(model.hyper.length_scales);
    ws.k_star(a) = sf2 * std::exp(-0.5 * ws.diff.squaredNorm());
  }
  GpPrediction p;
  const double mean_s = ws.k_star.dot(model.alpha);
  model.chol.triangularView<Eigen::Lower>().solveInPlace(ws.k_star);
  const double var_s = std::max(0.0, sf2 - ws.k_star.squaredNorm());
  const double scale2 = model.output_scale * model.output_scale;
  p.mean = model.output_mean + model.output_scale * mean_s;
  p.latent_variance = var_s * scale2;
  p.noise_variance = model.hyper.noise_std * model.hyper.noise_std + model.jitter * scale2;
  return p;
}

GpPrediction gp_predict(const GpModel& model, const Eigen::VectorXd& x) {
  if (x.size() != model.dim())
    throw InputError(
        fmt::format("GPR: query: expected {} input values, got {}", model.dim(), x.size()));
  GpWorkspace ws = make_gp_workspace(model);
  return gp_predict(model, x, ws);
}

}  // namespace mg::stats
