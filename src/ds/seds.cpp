#include "ds/seds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/check.hpp"
#include "core/error.hpp"
#include "ds/seds_layout.hpp"

namespace mg::ds {
namespace {

using namespace seds_layout;

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

constexpr std::array<std::pair<int, int>, 6> kLowerIndex{
    {{0, 0}, {1, 0}, {1, 1}, {2, 0}, {2, 1}, {2, 2}}};
const double kLog2Pi = std::log(2.0 * std::numbers::pi);

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

}  // namespace mg::ds
