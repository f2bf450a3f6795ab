#include "ds/seds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <nlopt.hpp>

#include "core/check.hpp"
#include "core/error.hpp"

namespace mg::ds {
namespace {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

constexpr int kCholeskySize = 6;
constexpr std::array<std::pair<int, int>, 6> kLowerIndex{
    {{0, 0}, {1, 0}, {1, 1}, {2, 0}, {2, 1}, {2, 2}}};
const double kLog2Pi = std::log(2.0 * std::numbers::pi);

// One Gaussian's block of the parameter vector: log prior, mu (3), the Cholesky parameters of
// Sigma (6), A (9, column-major), and with the likelihood objective those of C (6).
constexpr int kLogPrior = 0;
constexpr int kMu = 1;
constexpr int kSigma = kMu + 3;
constexpr int kA = kSigma + kCholeskySize;
constexpr int kC = kA + 9;

int block_size(SedsObjective objective) {
  return kC + (objective == SedsObjective::kLikelihood ? kCholeskySize : 0);
}

// Sigma = L L^T + floor I with L lower-triangular and log-diagonal parameters.
Mat3 cholesky_from_params(const double* p) {
  Mat3 l = Mat3::Zero();
  for (int i = 0; i < kCholeskySize; ++i) {
    const auto [r, c] = kLowerIndex[i];
    l(r, c) = (r == c) ? std::exp(p[i]) : p[i];
  }
  return l;
}

void params_from_covariance(const Mat3& sigma, double floor, double* p) {
  Mat3 s = 0.5 * (sigma + sigma.transpose());
  s.diagonal().array() -= floor;
  // Keep a positive definite remainder (at least a quarter of the diagonal).
  Eigen::SelfAdjointEigenSolver<Mat3> eig(s);
  Vec3 ev = eig.eigenvalues().cwiseMax(std::max(floor, 1e-12));
  s = eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
  const Mat3 l = Eigen::LLT<Mat3>(s).matrixL();
  for (int i = 0; i < kCholeskySize; ++i) {
    const auto [r, c] = kLowerIndex[i];
    p[i] = (r == c) ? std::log(l(r, c)) : l(r, c);
  }
}

// Gradient w.r.t. Cholesky parameters from G = dJ/dSigma (symmetric): dJ/dL = 2 G L.
void chain_cholesky(const Mat3& g, const Mat3& l, double* out) {
  const Mat3 dl = 2.0 * g * l;
  for (int i = 0; i < kCholeskySize; ++i) {
    const auto [r, c] = kLowerIndex[i];
    out[i] = (r == c) ? dl(r, c) * l(r, c) : dl(r, c);
  }
}

// Per-component quantities needed by the objective.
struct Prepared {
  double log_prior = 0.0;
  Vec3 mu;
  Mat3 a;
  Mat3 lx, sigma_inv;  // position covariance: Cholesky parameter matrix and inverse
  double log_norm_x = 0.0;
  Mat3 lc, c_inv;
  double log_norm_c = 0.0;
};

// Returns -0.5 (D log 2pi + log det Sigma) and the inverse of Sigma = L L^T + floor I.
double gaussian_normaliser(const Mat3& l, double floor, Mat3& inverse) {
  Mat3 sigma = l * l.transpose();
  sigma.diagonal().array() += floor;
  Eigen::LLT<Mat3> llt(sigma);
  inverse = llt.solve(Mat3::Identity());
  const double log_det = 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  return -0.5 * (3.0 * kLog2Pi + log_det);
}

double log_sum_exp(const Eigen::VectorXd& v) {
  const double m = v.maxCoeff();
  if (!std::isfinite(m)) return m;
  return m + std::log((v.array() - m).exp().sum());
}

}  // namespace

SedsObjective parse_seds_objective(const std::string& name) {
  if (name == "likelihood") return SedsObjective::kLikelihood;
  if (name == "mse") return SedsObjective::kMse;
  throw InputError(fmt::format("SEDS objective: expected 'likelihood' or 'mse', got '{}'", name));
}

std::string to_string(SedsObjective objective) {
  return objective == SedsObjective::kLikelihood ? "likelihood" : "mse";
}

void SedsOptions::validate() const {
  if (gaussians < 1 || gaussians > kMaxSedsGaussians)
    throw InputError(fmt::format("gaussians: expected 1..{} (the fit's cost grows as K^2), got {}",
                                 kMaxSedsGaussians, gaussians));
  if (max_evaluations < 1)
    throw InputError(fmt::format("max_evaluations: expected >= 1, got {}", max_evaluations));
  require_positive("relative_tolerance", relative_tolerance);
  require_positive("margin", margin);
  require_in_range("optimizer_margin", optimizer_margin, margin, 1e6);
  require_positive("covariance_floor", covariance_floor);
  if (max_rate != 0.0) require_in_range("max_rate", max_rate, 1.0, 1e6);
}

double stability_eigenvalue(const Mat3& a) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(a + a.transpose(), Eigen::EigenvaluesOnly);
  return eig.eigenvalues().maxCoeff();
}

int seds_num_parameters(int gaussians, SedsObjective objective) {
  return gaussians * block_size(objective);
}

Eigen::VectorXd pack_seds(const std::vector<SedsComponent>& components, SedsObjective objective,
                          double covariance_floor) {
  const int b = block_size(objective);
  Eigen::VectorXd p(static_cast<Eigen::Index>(components.size()) * b);
  for (std::size_t k = 0; k < components.size(); ++k) {
    const auto& c = components[k];
    double* q = p.data() + k * b;
    q[kLogPrior] = std::log(std::max(c.prior, 1e-12));
    for (int i = 0; i < 3; ++i) q[kMu + i] = c.mu[i];
    params_from_covariance(c.sigma, covariance_floor, q + kSigma);
    for (int i = 0; i < 9; ++i) q[kA + i] = c.a.data()[i];
    if (objective == SedsObjective::kLikelihood)
      params_from_covariance(c.c, covariance_floor, q + kC);
  }
  return p;
}

std::vector<SedsComponent> unpack_seds(const Eigen::VectorXd& params, SedsObjective objective,
                                       double covariance_floor,
                                       const std::vector<SedsComponent>& template_components) {
  const int b = block_size(objective);
  const auto k_count = static_cast<std::size_t>(params.size() / b);
  std::vector<SedsComponent> out(k_count);
  Eigen::VectorXd w(static_cast<Eigen::Index>(k_count));
  for (std::size_t k = 0; k < k_count; ++k)
    w[static_cast<Eigen::Index>(k)] = params[static_cast<Eigen::Index>(k * b + kLogPrior)];
  const double lse = log_sum_exp(w);
  for (std::size_t k = 0; k < k_count; ++k) {
    const double* q = params.data() + k * b;
    auto& c = out[k];
    c.prior = std::exp(q[kLogPrior] - lse);
    c.mu = Vec3(q[kMu], q[kMu + 1], q[kMu + 2]);
    const Mat3 lx = cholesky_from_params(q + kSigma);
    c.sigma = lx * lx.transpose();
    c.sigma.diagonal().array() += covariance_floor;
    c.a = Eigen::Map<const Mat3>(q + kA);
    if (objective == SedsObjective::kLikelihood) {
      const Mat3 lc = cholesky_from_params(q + kC);
      c.c = lc * lc.transpose();
      c.c.diagonal().array() += covariance_floor;
    } else if (k < template_components.size()) {
      c.c = template_components[k].c;
    }
  }
  return out;
}

double seds_objective(const Eigen::VectorXd& params, const SedsData& data, SedsObjective objective,
                      double covariance_floor,
                      const std::vector<SedsComponent>& /*template_components*/,
                      Eigen::VectorXd* gradient) {
  const int b = block_size(objective);
  const auto kc = static_cast<int>(params.size() / b);
  const bool like = objective == SedsObjective::kLikelihood;
  std::vector<Prepared> prep(static_cast<std::size_t>(kc));
  Eigen::VectorXd w(kc);
  for (int k = 0; k < kc; ++k) w[k] = params[k * b + kLogPrior];
  const double lse_w = log_sum_exp(w);
  for (int k = 0; k < kc; ++k) {
    const double* q = params.data() + k * b;
    auto& p = prep[static_cast<std::size_t>(k)];
    p.log_prior = q[kLogPrior] - lse_w;
    p.mu = Vec3(q[kMu], q[kMu + 1], q[kMu + 2]);
    p.lx = cholesky_from_params(q + kSigma);
    p.log_norm_x = gaussian_normaliser(p.lx, covariance_floor, p.sigma_inv);
    p.a = Eigen::Map<const Mat3>(q + kA);
    if (like) {
      p.lc = cholesky_from_params(q + kC);
      p.log_norm_c = gaussian_normaliser(p.lc, covariance_floor, p.c_inv);
    }
  }

  // Accumulators of dJ/d(log prior), dJ/dmu, dJ/dSigma (as sum dl z z^T and sum dl), dJ/dA, dJ/dC.
  Eigen::VectorXd g_logprior = Eigen::VectorXd::Zero(kc);
  std::vector<Vec3> g_mu(static_cast<std::size_t>(kc), Vec3::Zero());
  std::vector<Mat3> g_zz(static_cast<std::size_t>(kc), Mat3::Zero());
  std::vector<Mat3> g_a(static_cast<std::size_t>(kc), Mat3::Zero());
  std::vector<Mat3> g_uu(static_cast<std::size_t>(kc), Mat3::Zero());
  Eigen::VectorXd g_lsum = Eigen::VectorXd::Zero(kc);  // sum of dJ/dl_k (for the -Sigma^-1 term)
  Eigen::VectorXd g_csum = Eigen::VectorXd::Zero(kc);

  const auto n = data.size();
  const double inv_n = 1.0 / static_cast<double>(n);
  double value = 0.0;
  Eigen::VectorXd logit(kc), h(kc), dl(kc);
  std::vector<Vec3> z(static_cast<std::size_t>(kc)), zc(static_cast<std::size_t>(kc)),
      ay(static_cast<std::size_t>(kc));
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 y = data.y.col(i);
    const Vec3 yd = data.ydot.col(i);
    for (int k = 0; k < kc; ++k) {
      const auto& p = prep[static_cast<std::size_t>(k)];
      const auto ku = static_cast<std::size_t>(k);
      const Vec3 d = y - p.mu;
      z[ku] = p.sigma_inv * d;
      logit[k] = p.log_prior + p.log_norm_x - 0.5 * d.dot(z[ku]);
      ay[ku] = p.a * y;
      if (like) {
        const Vec3 u = yd - ay[ku];
        zc[ku] = p.c_inv * u;
        logit[k] += p.log_norm_c - 0.5 * u.dot(zc[ku]);
      }
    }
    const double lse = log_sum_exp(logit);
    h = (logit.array() - lse).exp();
    if (like) {
      value -= lse * inv_n;
      dl = -h * inv_n;
      if (gradient)
        for (int k = 0; k < kc; ++k) {
          const auto ku = static_cast<std::size_t>(k);
          g_a[ku] += dl[k] * zc[ku] * y.transpose();
          g_uu[ku] += dl[k] * zc[ku] * zc[ku].transpose();
          g_csum[k] += dl[k];
        }
    } else {
      Vec3 f = Vec3::Zero();
      for (int k = 0; k < kc; ++k) f += h[k] * ay[static_cast<std::size_t>(k)];
      const Vec3 e = f - yd;
      value += 0.5 * e.squaredNorm() * inv_n;
      if (gradient) {
        double gbar = 0.0;
        Eigen::VectorXd gk(kc);
        for (int k = 0; k < kc; ++k) {
          gk[k] = e.dot(ay[static_cast<std::size_t>(k)]);
          gbar += h[k] * gk[k];
          g_a[static_cast<std::size_t>(k)] += h[k] * inv_n * e * y.transpose();
        }
        dl = (h.array() * (gk.array() - gbar)).matrix() * inv_n;
      }
    }
    if (gradient)
      for (int k = 0; k < kc; ++k) {
        const auto ku = static_cast<std::size_t>(k);
        g_logprior[k] += dl[k];
        g_mu[ku] += dl[k] * z[ku];
        g_zz[ku] += dl[k] * z[ku] * z[ku].transpose();
        g_lsum[k] += dl[k];
      }
  }

  if (gradient) {
    gradient->setZero(params.size());
    const double sum_lp = g_logprior.sum();
    for (int k = 0; k < kc; ++k) {
      const auto& p = prep[static_cast<std::size_t>(k)];
      const auto ku = static_cast<std::size_t>(k);
      double* q = gradient->data() + k * b;
      q[kLogPrior] = g_logprior[k] - std::exp(p.log_prior) * sum_lp;
      for (int j = 0; j < 3; ++j) q[kMu + j] = g_mu[ku][j];
      const Mat3 gs = 0.5 * (g_zz[ku] - g_lsum[k] * p.sigma_inv);
      chain_cholesky(gs, p.lx, q + kSigma);
      for (int j = 0; j < 9; ++j) q[kA + j] = g_a[ku].data()[j];
      if (like) {
        const Mat3 gc = 0.5 * (g_uu[ku] - g_csum[k] * p.c_inv);
        chain_cholesky(gc, p.lc, q + kC);
      }
    }
  }
  return value;
}

Vec3 seds_velocity(const std::vector<SedsComponent>& components, const Vec3& y) {
  // Two passes (max, then sum) keep the weights finite far from every component.
  constexpr int kMaxK = 64;
  double logit[kMaxK];
  const int kc = std::min<int>(static_cast<int>(components.size()), kMaxK);
  double m = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < kc; ++k) {
    const auto& c = components[static_cast<std::size_t>(k)];
    const Eigen::LLT<Mat3> llt(c.sigma);
    const Vec3 d = y - c.mu;
    const Vec3 w = llt.matrixL().solve(d);
    const double log_det = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
    logit[k] = std::log(c.prior) - 0.5 * (log_det + w.squaredNorm());
    m = std::max(m, logit[k]);
  }
  double total = 0.0;
  Vec3 f = Vec3::Zero();
  for (int k = 0; k < kc; ++k) {
    const double h = std::exp(logit[k] - m);
    total += h;
    f += h * (components[static_cast<std::size_t>(k)].a * y);
  }
  return f / total;
}

stats::Gmm seds_to_gmm(const std::vector<SedsComponent>& components) {
  stats::Gmm g;
  const auto kc = static_cast<Eigen::Index>(components.size());
  g.priors.resize(kc);
  for (Eigen::Index k = 0; k < kc; ++k) {
    const auto& c = components[static_cast<std::size_t>(k)];
    g.priors[k] = c.prior;
    Eigen::VectorXd mean(6);
    mean << c.mu, c.a * c.mu;
    Eigen::MatrixXd cov(6, 6);
    cov.topLeftCorner<3, 3>() = c.sigma;
    cov.bottomLeftCorner<3, 3>() = c.a * c.sigma;
    cov.topRightCorner<3, 3>() = (c.a * c.sigma).transpose();
    cov.bottomRightCorner<3, 3>() = c.c + c.a * c.sigma * c.a.transpose();
    cov = 0.5 * (cov + cov.transpose()).eval();
    g.means.push_back(mean);
    g.covariances.push_back(cov);
  }
  g.priors /= g.priors.sum();
  return g;
}

std::vector<SedsComponent> seds_from_gmm(const stats::Gmm& gmm) {
  if (gmm.dim() != 6)
    throw InputError(fmt::format("SEDS GMM: expected dimension 6 (y, ydot), got {}", gmm.dim()));
  std::vector<SedsComponent> out;
  for (int k = 0; k < gmm.num_components(); ++k) {
    const auto& s = gmm.covariances[static_cast<std::size_t>(k)];
    SedsComponent c;
    c.prior = gmm.priors[k];
    c.mu = gmm.means[static_cast<std::size_t>(k)].head<3>();
    c.sigma = s.topLeftCorner<3, 3>();
    c.a = Mat3(s.bottomLeftCorner<3, 3>()) * c.sigma.inverse();
    c.c = Mat3(s.bottomRightCorner<3, 3>()) - c.a * Mat3(s.topRightCorner<3, 3>());
    c.c = 0.5 * (c.c + c.c.transpose()).eval();
    out.push_back(c);
  }
  return out;
}

double seds_check(const stats::Gmm& gmm, double* bias) {
  const auto comps = seds_from_gmm(gmm);
  double worst = -std::numeric_limits<double>::infinity();
  double worst_bias = 0.0;
  for (std::size_t k = 0; k < comps.size(); ++k) {
    worst = std::max(worst, stability_eigenvalue(comps[k].a));
    const Eigen::VectorXd& m = gmm.means[k];
    const Vec3 b = m.tail<3>() - comps[k].a * m.head<3>();
    worst_bias = std::max(worst_bias, b.norm() / (1.0 + m.tail<3>().norm()));
  }
  if (bias) *bias = worst_bias;
  return worst;
}

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
