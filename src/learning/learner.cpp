#include "learning/learner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "learning/model_selection.hpp"
#include "stats/gmr.hpp"

namespace mg::learning {
namespace {

using detail::apply;
using detail::fit_gmm_model;
using detail::GmmFit;
using detail::iota_dims;
using detail::make_standardizer;

double nlpd_term(double y, double mean, double var) {
  return 0.5 * std::log(2.0 * std::numbers::pi * var) + 0.5 * (y - mean) * (y - mean) / var;
}

}  // namespace

std::string_view method_name(Method m) {
  switch (m) {
    case Method::kGpr:
      return "gpr";
    case Method::kGmr:
      return "gmr";
    case Method::kJointGmr:
      return "joint-gmr";
  }
  return "?";
}

Method parse_method(std::string_view name) {
  for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr})
    if (name == method_name(m)) return m;
  throw InputError(fmt::format("method: expected one of gpr, gmr, joint-gmr, got '{}'", name));
}

std::string_view selection_name(ComponentSelection s) {
  return s == ComponentSelection::kBic ? "bic" : "cv";
}

ComponentSelection parse_selection(std::string_view name) {
  if (name == "bic") return ComponentSelection::kBic;
  if (name == "cv") return ComponentSelection::kCrossValidation;
  throw InputError(fmt::format("component selection: expected bic or cv, got '{}'", name));
}

void TrainOptions::validate() const {
  if (num_gaussians < 0)
    throw InputError(
        fmt::format("number of Gaussians: expected >= 1 (or 0 = choose), got {}", num_gaussians));
  if (max_gaussians < 1)
    throw InputError(fmt::format("max Gaussians: expected >= 1, got {}", max_gaussians));
  if (cv_folds < 2)
    throw InputError(fmt::format("cross-validation folds: expected >= 2, got {}", cv_folds));
  if (restarts < 1 || restarts > kMaxRestarts)
    throw InputError(fmt::format("restarts: expected 1..{}, got {}", kMaxRestarts, restarts));
  em.validate();
  // 0 lets a component collapse onto a few points: the model would be written and then rejected.
  if (!choose_reg_covar && !(em.reg_covar > 0.0))
    throw InputError(
        fmt::format("reg_covar: expected a number > 0 (standardised units), got {}", em.reg_covar));
  if (choose_reg_covar) {
    if (!(reg_covar_rows > 0.0) || !std::isfinite(reg_covar_rows))
      throw InputError(
          fmt::format("reg_covar_rows: expected a number > 0, got {}", reg_covar_rows));
    if (reg_covar_grid.empty()) throw InputError("reg_covar grid: expected at least one value");
    for (double r : reg_covar_grid)
      if (!(r > 0.0) || !std::isfinite(r))
        throw InputError(fmt::format("reg_covar grid: expected numbers > 0, got {}", r));
  }
  for (const auto& g : gpr) g.validate();
}

Model train(const Dataset& data, const TrainOptions& options) {
  options.validate();
  const int n = data.size();
  const int ni = static_cast<int>(data.input_names.size());
  const int no = static_cast<int>(data.output_names.size());
  if (n < 2)
    throw InputError(fmt::format("{}: expected at least 2 training rows, got {}", data.source, n));
  if (data.inputs.cols() != ni || data.outputs.cols() != no || data.outputs.rows() != n || ni < 1 ||
      no < 1)
    throw InputError(fmt::format("{}: inconsistent dataset shape", data.source));
  if (!options.gpr.empty() && options.gpr.size() != 1 && static_cast<int>(options.gpr.size()) != no)
    throw InputError(fmt::format("GPR options: expected 1 or {} sets (one per output), got {}", no,
                                 options.gpr.size()));

  Model m;
  m.method = options.method;
  m.input_names = data.input_names;
  m.output_names = data.output_names;
  m.seed = options.seed;
  m.reports.resize(static_cast<std::size_t>(no));
  const double log_n = std::log(static_cast<double>(n));

  if (options.method == Method::kGpr) {
    if (n > kMaxGprRows)
      throw InputError(fmt::format(
          "{}: {} training rows: GPR takes at most {} (its fit grows as N^3: minutes beyond); "
          "use --method gmr or joint-gmr, or fewer rows",
          data.source, n, kMaxGprRows));
    for (int o = 0; o < no; ++o) {
      stats::GprOptions g = options.gpr.empty()       ? stats::GprOptions{}
                            : options.gpr.size() == 1 ? options.gpr[0]
                                                      : options.gpr[static_cast<std::size_t>(o)];
      g.restarts = options.restarts;
      mg::Rng rng(mg::derive_seed(options.seed, static_cast<std::uint64_t>(o)));
      m.gps.push_back(stats::fit_gpr(data.inputs, data.outputs.col(o), rng, g));
      const stats::GpModel& gp = m.gps.back();
      FitReport& r = m.reports[static_cast<std::size_t>(o)];
      r.length_scales = gp.hyper.length_scales;
      r.signal_std = gp.hyper.signal_std;
      r.noise_std = gp.hyper.noise_std;
      r.log_marginal_likelihood = gp.log_marginal_likelihood;
    }
    return m;
  }

  m.input_standardizer = make_standardizer(data.inputs);
  m.output_standardizer = make_standardizer(data.outputs);
  const Eigen::MatrixXd xs = apply(m.input_standardizer, data.inputs);
  const Eigen::MatrixXd ys = apply(m.output_standardizer, data.outputs);
  stats::EmOptions em = options.em;
  em.kmeans_restarts = options.restarts;
  TrainOptions opt = options;
  opt.em = em;
  const double log_in_scale = m.input_standardizer.scale.array().log().sum();
  auto fit = [&](const Eigen::MatrixXd& y_block, double log_out_scale, std::uint64_t stream) {
    Eigen::MatrixXd joint(n, ni + y_block.cols());
    joint << xs, y_block;
    const GmmFit fitted = fit_gmm_model(joint, ni, opt, mg::derive_seed(options.seed, stream));
    const stats::EmResult& r = fitted.em;
    try {
      r.gmm.validate();
    } catch (const InputError& e) {
      throw NumericalError(
          fmt::format("{}: the GMM fit is degenerate ({}); a larger reg_covar than {:g} is needed",
                      data.source, e.what(), fitted.reg_covar));
    }
    FitReport rep;
    rep.n_gaussians = r.gmm.num_components();
    rep.reg_covar = fitted.reg_covar;
    // Back to data units: the standardisation's Jacobian.
    rep.log_likelihood = r.log_likelihood - n * (log_in_scale + log_out_scale);
    rep.bic = -2.0 * rep.log_likelihood +
              stats::gmm_num_parameters(rep.n_gaussians, static_cast<int>(joint.cols())) * log_n;
    m.gmms.push_back(r.gmm);
    return rep;
  };
  if (options.method == Method::kGmr) {
    for (int o = 0; o < no; ++o)
      m.reports[static_cast<std::size_t>(o)] =
          fit(ys.col(o), std::log(m.output_standardizer.scale(o)), static_cast<std::uint64_t>(o));
  } else {
    const FitReport rep = fit(ys, m.output_standardizer.scale.array().log().sum(), 0);
    for (auto& r : m.reports) r = rep;
  }
  return m;
}

namespace {
// A model read from a file can hold values (means, scales) that overflow in a prediction: say
// so rather than print NaN.
Predictions checked(Predictions p) {
  for (Eigen::Index i = 0; i < p.mean.rows(); ++i)
    if (!p.mean.row(i).allFinite() || !p.std.row(i).allFinite())
      throw NumericalError(fmt::format(
          "predict: query row {}: the model gives a non-finite prediction (values in the "
          "model or the query beyond what double precision can carry)",
          i + 1));
  return p;
}

/// The columns of `queries` (by m's inputs) that m's prior reads, in its order; the queries as
/// they are when the inputs agree.
Eigen::MatrixXd prior_columns(const Model& m, const Eigen::MatrixXd& queries) {
  if (m.prior->input_names == m.input_names) return queries;
  Eigen::MatrixXd q(queries.rows(), m.prior->num_inputs());
  for (int c = 0; c < m.prior->num_inputs(); ++c) {
    const auto& name = m.prior->input_names[static_cast<std::size_t>(c)];
    const auto at = std::find(m.input_names.begin(), m.input_names.end(), name);
    if (at == m.input_names.end())
      throw InputError(fmt::format("predict: the prior's input '{}' is not the model's", name));
    q.col(c) = queries.col(at - m.input_names.begin());
  }
  return q;
}

}  // namespace

Predictions predict(const Model& m, const Eigen::MatrixXd& queries) {
  const int ni = m.num_inputs();
  const int no = m.num_outputs();
  if (queries.cols() != ni)
    throw InputError(
        fmt::format("predict: queries: expected {} input columns, got {}", ni, queries.cols()));
  if (!queries.allFinite()) throw InputError("predict: queries: expected finite values");
  const Eigen::Index n = queries.rows();
  Predictions p;
  p.mean.resize(n, no);
  p.std.resize(n, no);
  if (m.prior) {
    Model residual = m;
    residual.prior.reset();
    const Predictions base = predict(*m.prior, prior_columns(m, queries));
    const Predictions correction = predict(residual, queries);
    p.mean = base.mean + correction.mean;
    p.std = (base.std.array().square() + correction.std.array().square()).sqrt().matrix();
    return checked(p);
  }
  if (m.method == Method::kGpr) {
    for (int o = 0; o < no; ++o) {
      const stats::GpModel& gp = m.gps[static_cast<std::size_t>(o)];
      stats::GpWorkspace ws = stats::make_gp_workspace(gp);
      for (Eigen::Index i = 0; i < n; ++i) {
        const stats::GpPrediction g = stats::gp_predict(gp, queries.row(i).transpose(), ws);
        p.mean(i, o) = g.mean;
        p.std(i, o) = std::sqrt(g.variance());
      }
    }
    return checked(p);
  }
  const Eigen::MatrixXd xs = apply(m.input_standardizer, queries);
  const bool joint = m.method == Method::kJointGmr;
  for (std::size_t g = 0; g < m.gmms.size(); ++g) {
    const int outs = joint ? no : 1;
    const stats::GmrConditioner cond(m.gmms[g], iota_dims(0, ni), iota_dims(ni, outs));
    auto ws = cond.make_workspace();
    Eigen::VectorXd mean(outs);
    Eigen::MatrixXd cov(outs, outs);
    for (Eigen::Index i = 0; i < n; ++i) {
      cond.predict(xs.row(i).transpose(), mean, cov, ws);
      for (int k = 0; k < outs; ++k) {
        const int o = joint ? k : static_cast<int>(g);
        const double s = m.output_standardizer.scale(o);
        p.mean(i, o) = m.output_standardizer.mean(o) + s * mean(k);
        p.std(i, o) = s * std::sqrt(std::max(cov(k, k), 0.0));
      }
    }
  }
  return checked(p);
}

std::vector<BeyondTraining> beyond_training(const Model& m, const Predictions& p) {
  std::vector<BeyondTraining> out;
  if (m.method == Method::kGpr || m.prior) return out;  // GPR reverts to its mean far from data
  for (Eigen::Index i = 0; i < p.mean.rows(); ++i)
    for (int o = 0; o < m.num_outputs(); ++o) {
      const double z =
          (p.mean(i, o) - m.output_standardizer.mean(o)) / m.output_standardizer.scale(o);
      if (std::abs(z) > kMaxPredictionSpread) out.push_back({static_cast<int>(i), o, std::abs(z)});
    }
  return out;
}

std::vector<Score> score(const Model& m, const Dataset& v) {
  if (v.input_names != m.input_names || v.output_names != m.output_names)
    throw InputError(fmt::format("{}: expected columns {} -> {} (as the model), got {} -> {}",
                                 v.source, fmt::join(m.input_names, ","),
                                 fmt::join(m.output_names, ","), fmt::join(v.input_names, ","),
                                 fmt::join(v.output_names, ",")));
  const Predictions p = predict(m, v.inputs);
  std::vector<Score> out(static_cast<std::size_t>(m.num_outputs()));
  const double n = static_cast<double>(v.size());
  for (int o = 0; o < m.num_outputs(); ++o) {
    Score& s = out[static_cast<std::size_t>(o)];
    for (Eigen::Index i = 0; i < v.inputs.rows(); ++i) {
      const double var = std::max(p.std(i, o) * p.std(i, o), std::numeric_limits<double>::min());
      s.mse += (v.outputs(i, o) - p.mean(i, o)) * (v.outputs(i, o) - p.mean(i, o)) / n;
      s.nlpd += nlpd_term(v.outputs(i, o), p.mean(i, o), var) / n;
    }
  }
  return out;
}

}  // namespace mg::learning
