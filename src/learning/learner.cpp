#include "learning/learner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "core/json_io.hpp"
#include "core/rng.hpp"
#include "stats/gmm_io.hpp"
#include "stats/gmr.hpp"

namespace mg::learning {
namespace {

Standardizer make_standardizer(const Eigen::MatrixXd& m) {
  Standardizer s;
  s.mean = m.colwise().mean().transpose();
  s.scale.resize(m.cols());
  for (Eigen::Index j = 0; j < m.cols(); ++j) {
    const double sd = std::sqrt((m.col(j).array() - s.mean(j)).square().mean());
    // A column whose spread is rounding noise of its values is constant: dividing by that noise
    // would blow a query a few ulps away up to 1e13 standard deviations (and GMR's linear
    // extrapolation with it).
    const double magnitude = m.col(j).cwiseAbs().maxCoeff();
    const bool negligible = !(sd > kNegligibleSpread * magnitude) || !std::isfinite(sd);
    s.scale(j) = negligible ? 1.0 : sd;
  }
  return s;
}

Eigen::MatrixXd apply(const Standardizer& s, const Eigen::MatrixXd& m) {
  return (m.rowwise() - s.mean.transpose()).array().rowwise() / s.scale.transpose().array();
}

std::vector<int> iota_dims(int first, int count) {
  std::vector<int> v(static_cast<std::size_t>(count));
  std::iota(v.begin(), v.end(), first);
  return v;
}

// Squared GMR error (standardised outputs, summed over outputs) of every row when it is held
// out, K components, by cross-validation.
Eigen::VectorXd cv_errors(const Eigen::MatrixXd& joint, int num_inputs, int k, int folds,
                          const std::vector<int>& fold_of, std::uint64_t seed,
                          const stats::EmOptions& em) {
  const Eigen::Index n = joint.rows();
  const int num_outputs = static_cast<int>(joint.cols()) - num_inputs;
  Eigen::VectorXd err = Eigen::VectorXd::Zero(n);
  for (int f = 0; f < folds; ++f) {
    std::vector<Eigen::Index> train_rows, test_rows;
    for (Eigen::Index i = 0; i < n; ++i)
      (fold_of[static_cast<std::size_t>(i)] == f ? test_rows : train_rows).push_back(i);
    if (test_rows.empty()) continue;
    if (static_cast<int>(train_rows.size()) < k)
      return Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
    Eigen::MatrixXd train(static_cast<Eigen::Index>(train_rows.size()), joint.cols());
    for (std::size_t i = 0; i < train_rows.size(); ++i)
      train.row(static_cast<Eigen::Index>(i)) = joint.row(train_rows[i]);
    mg::Rng rng(mg::derive_seed(seed, static_cast<std::uint64_t>(1000 * k + f)));
    const stats::Gmm g = stats::fit_gmm(train, k, rng, em).gmm;
    const stats::GmrConditioner cond(g, iota_dims(0, num_inputs),
                                     iota_dims(num_inputs, num_outputs));
    auto ws = cond.make_workspace();
    Eigen::VectorXd out(num_outputs);
    for (Eigen::Index r : test_rows) {
      cond.predict_mean(joint.row(r).head(num_inputs).transpose(), out, ws);
      err(r) = (out - joint.row(r).tail(num_outputs).transpose()).squaredNorm();
    }
  }
  return err;
}

// Seeded shuffle of n rows into `folds` folds.
std::vector<int> make_folds(int n, int folds, mg::Rng& rng) {
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  for (int i = n - 1; i > 0; --i)
    std::swap(order[static_cast<std::size_t>(i)], order[rng() % static_cast<std::uint64_t>(i + 1)]);
  std::vector<int> fold_of(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    fold_of[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])] = i % folds;
  return fold_of;
}

// cv_errors, or +inf everywhere if a fold's fit fails (a value of reg_covar too small for the
// data).
Eigen::VectorXd cv_errors_or_inf(const Eigen::MatrixXd& joint, int num_inputs, int k, int folds,
                                 const std::vector<int>& fold_of, std::uint64_t seed,
                                 const stats::EmOptions& em) {
  const auto failed = [&] {
    return Eigen::VectorXd::Constant(joint.rows(), std::numeric_limits<double>::infinity());
  };
  try {
    const Eigen::VectorXd e = cv_errors(joint, num_inputs, k, folds, fold_of, seed, em);
    return e.allFinite() ? e : failed();
  } catch (const Error&) {
    return failed();
  }
}

double mean_or_inf(const Eigen::VectorXd& e) {
  return e.allFinite() ? e.mean() : std::numeric_limits<double>::infinity();
}

// Whether `candidate`'s held-out errors are measurably below `baseline`'s: lower by at least
// min_gain of the baseline's mean, and the paired mean difference more than two standard
// errors below zero (rows are the pairs: the same folds hold the same rows out).
bool measurably_lower(const Eigen::VectorXd& candidate, const Eigen::VectorXd& baseline,
                      double min_gain) {
  if (candidate.size() == 0 || !candidate.allFinite()) return false;
  if (baseline.size() != candidate.size() || !baseline.allFinite())
    return true;  // the baseline failed
  const Eigen::Index n = candidate.size();
  if (n < 2) return false;
  const Eigen::VectorXd d = candidate - baseline;
  const double mean = d.mean();
  const double se = std::sqrt((d.array() - mean).square().sum() / static_cast<double>(n - 1) /
                              static_cast<double>(n));
  return mean < -min_gain * baseline.mean() && mean < -2.0 * se;
}

struct GmmFit {
  stats::EmResult em;
  double reg_covar = 0.0;
};

GmmFit fit_gmm_model(const Eigen::MatrixXd& joint, int num_inputs, const TrainOptions& opt,
                     std::uint64_t seed) {
  const int n = static_cast<int>(joint.rows());
  mg::Rng rng(seed);
  if (opt.num_gaussians > n)
    throw InputError(fmt::format(
        "number of Gaussians: expected at most {} (the number of training rows), got {}", n,
        opt.num_gaussians));
  const int folds = std::min(opt.cv_folds, n);
  mg::Rng fold_rng(mg::derive_seed(seed, 77));
  const std::vector<int> fold_of = make_folds(n, folds, fold_rng);
  const std::vector<double> regs =
      opt.choose_reg_covar ? opt.reg_covar_grid : std::vector<double>{opt.em.reg_covar};

  // The default reg_covar is a prior of fixed strength: reg_covar_rows / N (em.reg_covar at
  // most, 1e-2: best on the smallest noisy sets), as a Normal-inverse-Wishart prior's weight
  // falls as 1/N. It stays unless another value's held-out GMR error is measurably lower
  // (measurably_lower: by kRegSwitchGain and two paired standard errors). Below
  // kMinRowsForRegSelection rows (folds of one or two points) the default is kept.
  constexpr double kRegSwitchGain = 0.05;
  constexpr int kMinRowsForRegSelection = 10;
  const double default_reg =
      opt.choose_reg_covar
          ? std::min(opt.em.reg_covar, std::max(*std::min_element(regs.begin(), regs.end()),
                                                opt.reg_covar_rows / static_cast<double>(n)))
          : opt.em.reg_covar;
  int best_k = opt.num_gaussians;
  double best_reg = default_reg;
  auto choose = [&](const std::vector<int>& ks) {
    Eigen::VectorXd err_default, err_other;
    double best_default = std::numeric_limits<double>::infinity(), best_other = best_default;
    int k_default = ks.front(), k_other = ks.front();
    double reg_other = default_reg;
    for (int k : ks) {
      stats::EmOptions em = opt.em;
      em.reg_covar = default_reg;
      Eigen::VectorXd e = cv_errors_or_inf(joint, num_inputs, k, folds, fold_of, seed, em);
      if (const double m = mean_or_inf(e); m < best_default * (1.0 - 1e-12)) {
        best_default = m;
        err_default = std::move(e);
        k_default = k;
      }
      if (n < kMinRowsForRegSelection) continue;
      for (auto it = regs.rbegin(); it != regs.rend(); ++it) {
        if (*it == default_reg) continue;
        em.reg_covar = *it;
        Eigen::VectorXd eo = cv_errors_or_inf(joint, num_inputs, k, folds, fold_of, seed, em);
        if (const double m = mean_or_inf(eo); m < best_other * (1.0 - 1e-2)) {
          best_other = m;
          err_other = std::move(eo);
          k_other = k;
          reg_other = *it;
        }
      }
    }
    if (!std::isfinite(best_default) && !std::isfinite(best_other))
      throw NumericalError(fmt::format(
          "GMM fit: every cross-validation fit failed (K in {}..{}, reg_covar in {}..{})",
          ks.front(), ks.back(), regs.front(), regs.back()));
    if (measurably_lower(err_other, err_default,
                         kRegSwitchGain)) {  // false when no other value fitted
      best_k = k_other;
      best_reg = reg_other;
    } else {
      best_k = k_default;
      best_reg = default_reg;
    }
  };
  if (opt.num_gaussians > 0) {
    if (regs.size() > 1) choose({opt.num_gaussians});
  } else if (opt.selection == ComponentSelection::kBic) {
    // K by BIC at the fixed em.reg_covar, then reg_covar by cross-validation at that K.
    stats::EmResult by_bic = stats::fit_gmm_bic(joint, opt.max_gaussians, rng, opt.em);
    if (regs.size() == 1) return {std::move(by_bic), default_reg};
    best_k = by_bic.gmm.num_components();
    choose({best_k});
    if (best_reg == default_reg)
      return {std::move(by_bic), default_reg};  // the same fit as without the choice
  } else {
    std::vector<int> ks;
    for (int k = 1; k <= std::min(opt.max_gaussians, n); ++k) ks.push_back(k);
    choose(ks);
  }
  stats::EmOptions em = opt.em;
  em.reg_covar = best_reg;
  return {stats::fit_gmm(joint, best_k, rng, em), best_reg};
}

double nlpd_term(double y, double mean, double var) {
  return 0.5 * std::log(2.0 * std::numbers::pi * var) + 0.5 * (y - mean) * (y - mean) / var;
}

// ---- JSON reading helpers: every failure names the field.
const nlohmann::json& field(const nlohmann::json& j, const char* key, std::string_view where) {
  if (!j.is_object())
    throw InputError(fmt::format("{}: expected a JSON object, got {}", where, j.type_name()));
  if (!j.contains(key)) throw InputError(fmt::format("{}: missing field '{}'", where, key));
  return j.at(key);
}
double number(const nlohmann::json& j, const char* key, std::string_view where) {
  const auto& v = field(j, key, where);
  if (!v.is_number())
    throw InputError(fmt::format("{}.{}: expected a number, got {}", where, key, v.type_name()));
  const double d = v.get<double>();
  if (!std::isfinite(d))
    throw InputError(fmt::format("{}.{}: expected a finite number", where, key));
  return d;
}
std::string text(const nlohmann::json& j, const char* key, std::string_view where) {
  const auto& v = field(j, key, where);
  if (!v.is_string())
    throw InputError(fmt::format("{}.{}: expected a string, got {}", where, key, v.type_name()));
  return v.get<std::string>();
}
std::vector<std::string> names(const nlohmann::json& j, const char* key, std::string_view where) {
  const auto& v = field(j, key, where);
  if (!v.is_array() || v.empty())
    throw InputError(fmt::format("{}.{}: expected a non-empty array of names", where, key));
  std::vector<std::string> out;
  for (const auto& e : v) {
    if (!e.is_string() || e.get<std::string>().empty())
      throw InputError(
          fmt::format("{}.{}: expected non-empty strings, got {}", where, key, e.dump()));
    out.push_back(e.get<std::string>());
  }
  return out;
}

nlohmann::json report_json(const Model& m, int o) {
  const FitReport& r = m.reports[static_cast<std::size_t>(o)];
  nlohmann::json j;
  if (m.method == Method::kGpr) {
    j["length_scales"] = stats::vector_to_json(r.length_scales);
    j["signal_std"] = r.signal_std;
    j["noise_std"] = r.noise_std;
    j["log_marginal_likelihood"] = r.log_marginal_likelihood;
  } else {
    j["n_gaussians"] = r.n_gaussians;
    j["reg_covar"] = r.reg_covar;
    j["log_likelihood"] = r.log_likelihood;
    j["bic"] = r.bic;
  }
  return j;
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
    const Predictions base = predict(*m.prior, queries);
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

nlohmann::json report_to_json(const Model& m) {
  nlohmann::json j = nlohmann::json::object();
  for (int o = 0; o < m.num_outputs(); ++o)
    j[m.output_names[static_cast<std::size_t>(o)]] = report_json(m, o);
  return j;
}

nlohmann::json model_to_json(const Model& m) {
  nlohmann::json j;
  j["format"] = "minigolf-learner";
  j["format_version"] = kModelFormatVersion;
  j["method"] = std::string(method_name(m.method));
  j["inputs"] = m.input_names;
  j["outputs"] = m.output_names;
  j["seed"] = m.seed;
  if (m.method == Method::kGpr) {
    j["training_inputs"] = stats::matrix_to_json(m.gps.front().inputs);
    j["gps"] = nlohmann::json::array();
    for (std::size_t o = 0; o < m.gps.size(); ++o) {
      const stats::GpModel& gp = m.gps[o];
      j["gps"].push_back({{"output", m.output_names[o]},
                          {"length_scales", stats::vector_to_json(gp.hyper.length_scales)},
                          {"signal_std", gp.hyper.signal_std},
                          {"noise_std", gp.hyper.noise_std},
                          {"training_targets", stats::vector_to_json(gp.targets)}});
    }
  } else {
    j["input_standardization"] = {{"mean", stats::vector_to_json(m.input_standardizer.mean)},
                                  {"scale", stats::vector_to_json(m.input_standardizer.scale)}};
    j["output_standardization"] = {{"mean", stats::vector_to_json(m.output_standardizer.mean)},
                                   {"scale", stats::vector_to_json(m.output_standardizer.scale)}};
    j["gmms"] = nlohmann::json::array();
    for (const auto& g : m.gmms) j["gmms"].push_back(stats::gmm_to_json(g));
  }
  if (!m.fixed.empty()) {
    j["fixed"] = nlohmann::json::object();
    for (const auto& [n, v] : m.fixed) j["fixed"][n] = v;
  }
  j["fit"] = report_to_json(m);
  if (m.prior) j["prior"] = model_to_json(*m.prior);
  return j;
}

namespace {
Model model_from_json_at(const nlohmann::json& j, std::string_view where, int depth);
}  // namespace

Model model_from_json(const nlohmann::json& j, std::string_view where) {
  return model_from_json_at(j, where, 0);
}

namespace {
Model model_from_json_at(const nlohmann::json& j, std::string_view where, int depth) {
  const std::string fmt_name = text(j, "format", where);
  if (fmt_name != "minigolf-learner")
    throw InputError(
        fmt::format("{}: format: expected \"minigolf-learner\", got \"{}\"", where, fmt_name));
  const auto& ver = field(j, "format_version", where);
  if (!ver.is_number_integer() || ver.get<long long>() != kModelFormatVersion)
    throw InputError(
        fmt::format("{}: format_version: expected {} (this build reads version {}), got {}", where,
                    kModelFormatVersion, kModelFormatVersion, ver.dump()));
  Model m;
  m.method = parse_method(text(j, "method", where));
  m.input_names = names(j, "inputs", where);
  m.output_names = names(j, "outputs", where);
  const auto& seed = field(j, "seed", where);
  if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<long long>() >= 0))
    throw InputError(
        fmt::format("{}.seed: expected a non-negative integer, got {}", where, seed.dump()));
  m.seed = seed.get<std::uint64_t>();
  if (j.contains("fixed")) {
    const auto& fx = j["fixed"];
    if (!fx.is_object())
      throw InputError(fmt::format("{}.fixed: expected an object of numbers", where));
    for (auto it = fx.begin(); it != fx.end(); ++it) {
      if (!it.value().is_number() || !std::isfinite(it.value().get<double>()))
        throw InputError(fmt::format("{}.fixed.{}: expected a finite number, got {}", where,
                                     it.key(), it.value().dump()));
      for (const auto& o : m.output_names)
        if (o == it.key())
          throw InputError(fmt::format("{}.fixed.{}: is also an output", where, it.key()));
      m.fixed.emplace_back(it.key(), it.value().get<double>());
    }
  }
  const int ni = m.num_inputs();
  const int no = m.num_outputs();
  const std::string w(where);

  if (m.method == Method::kGpr) {
    const Eigen::MatrixXd x =
        stats::json_to_matrix(field(j, "training_inputs", where), w + ".training_inputs");
    if (x.cols() != ni || x.rows() < 1)
      throw InputError(fmt::format("{}.training_inputs: expected rows of {} values, got {} x {}",
                                   where, ni, x.rows(), x.cols()));
    const auto& gps = field(j, "gps", where);
    if (!gps.is_array() || static_cast<int>(gps.size()) != no)
      throw InputError(
          fmt::format("{}.gps: expected an array of {} GPs (one per output)", where, no));
    for (int o = 0; o < no; ++o) {
      const std::string gw = fmt::format("{}.gps[{}]", where, o);
      const auto& g = gps[static_cast<std::size_t>(o)];
      if (text(g, "output", gw) != m.output_names[static_cast<std::size_t>(o)])
        throw InputError(fmt::format("{}.output: expected \"{}\"", gw,
                                     m.output_names[static_cast<std::size_t>(o)]));
      stats::GpHyperparameters h;
      h.length_scales = stats::json_to_vector(field(g, "length_scales", gw), gw + ".length_scales");
      h.signal_std = number(g, "signal_std", gw);
      h.noise_std = number(g, "noise_std", gw);
      const Eigen::VectorXd y =
          stats::json_to_vector(field(g, "training_targets", gw), gw + ".training_targets");
      try {
        m.gps.push_back(stats::make_gp_model(x, y, h));
      } catch (const Error& e) {
        throw InputError(fmt::format("{}: {}", gw, e.what()));
      }
    }
  } else {
    auto standardizer = [&](const char* key, int dim) {
      const auto& s = field(j, key, where);
      const std::string sw = fmt::format("{}.{}", where, key);
      Standardizer st;
      st.mean = stats::json_to_vector(field(s, "mean", sw), sw + ".mean");
      st.scale = stats::json_to_vector(field(s, "scale", sw), sw + ".scale");
      if (st.mean.size() != dim || st.scale.size() != dim || !(st.scale.array() > 0.0).all())
        throw InputError(fmt::format("{}: expected {} means and {} positive scales", sw, dim, dim));
      return st;
    };
    m.input_standardizer = standardizer("input_standardization", ni);
    m.output_standardizer = standardizer("output_standardization", no);
    const auto& gmms = field(j, "gmms", where);
    const int expected = m.method == Method::kGmr ? no : 1;
    const int dim = m.method == Method::kGmr ? ni + 1 : ni + no;
    if (!gmms.is_array() || static_cast<int>(gmms.size()) != expected)
      throw InputError(fmt::format("{}.gmms: expected an array of {} GMMs", where, expected));
    for (int g = 0; g < expected; ++g) {
      const std::string gw = fmt::format("{}.gmms[{}]", where, g);
      m.gmms.push_back(stats::gmm_from_json(gmms[static_cast<std::size_t>(g)], gw));
      if (m.gmms.back().dim() != dim)
        throw InputError(
            fmt::format("{}: expected dimension {}, got {}", gw, dim, m.gmms.back().dim()));
    }
  }

  // Fit summaries: recorded at training time (informational).
  const auto& fit = field(j, "fit", where);
  m.reports.resize(static_cast<std::size_t>(no));
  for (int o = 0; o < no; ++o) {
    const std::string& name = m.output_names[static_cast<std::size_t>(o)];
    const std::string fw = fmt::format("{}.fit.{}", where, name);
    const auto& r = field(fit, name.c_str(), fmt::format("{}.fit", where));
    FitReport& rep = m.reports[static_cast<std::size_t>(o)];
    if (m.method == Method::kGpr) {
      rep.length_scales =
          stats::json_to_vector(field(r, "length_scales", fw), fw + ".length_scales");
      rep.signal_std = number(r, "signal_std", fw);
      rep.noise_std = number(r, "noise_std", fw);
      rep.log_marginal_likelihood = number(r, "log_marginal_likelihood", fw);
    } else {
      const auto& k = field(r, "n_gaussians", fw);
      if (!k.is_number_integer())
        throw InputError(fmt::format("{}.n_gaussians: expected an integer", fw));
      rep.n_gaussians = k.get<int>();
      if (r.is_object() && r.contains("reg_covar")) rep.reg_covar = number(r, "reg_covar", fw);
      rep.log_likelihood = number(r, "log_likelihood", fw);
      rep.bic = number(r, "bic", fw);
    }
  }
  if (j.contains("prior")) {
    if (depth + 1 >= kMaxPriorDepth)
      throw InputError(
          fmt::format("{}.prior: residual models nest at most {} deep", where, kMaxPriorDepth));
    auto prior = std::make_shared<Model>(
        model_from_json_at(j["prior"], fmt::format("{}.prior", where), depth + 1));
    if (prior->input_names != m.input_names || prior->output_names != m.output_names)
      throw InputError(fmt::format("{}.prior: expected the residual's inputs and outputs", where));
    if (prior->fixed != m.fixed)
      throw InputError(fmt::format("{}.prior: expected the residual's fixed values", where));
    m.prior = std::move(prior);
  }
  return m;
}
}  // namespace

void save_model(const Model& model, const std::filesystem::path& path) {
  write_file_atomic(path, model_to_json(model).dump(2) + "\n");
}

Model load_model(const std::filesystem::path& path) {
  return model_from_json(read_json_file(path), path.string());
}

}  // namespace mg::learning
