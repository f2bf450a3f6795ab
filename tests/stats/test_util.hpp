#pragma once
// Shared helpers for the stats tests: seeded samplers and brute-force densities.
#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Dense>

#include "core/rng.hpp"
#include "stats/gmm.hpp"

namespace mg::stats::testing {

inline Eigen::MatrixXd sample_gaussian(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                                       int n, mg::Rng& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::MatrixXd l = Eigen::LLT<Eigen::MatrixXd>(cov).matrixL();
  Eigen::MatrixXd out(n, mean.size());
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd z(mean.size());
    for (Eigen::Index d = 0; d < mean.size(); ++d) z(d) = normal(rng);
    out.row(i) = (mean + l * z).transpose();
  }
  return out;
}

// Density by the textbook formula with an explicit inverse and determinant (an independent route).
inline double naive_gaussian_pdf(const Eigen::VectorXd& x, const Eigen::VectorXd& mean,
                                 const Eigen::MatrixXd& cov) {
  const Eigen::VectorXd d = x - mean;
  const double q = d.dot(cov.inverse() * d);
  return std::exp(-0.5 * q) /
         std::sqrt(std::pow(2.0 * std::numbers::pi, static_cast<double>(x.size())) *
                   cov.determinant());
}

inline double naive_gmm_pdf(const Gmm& g, const Eigen::VectorXd& x) {
  double p = 0.0;
  for (int k = 0; k < g.num_components(); ++k)
    p += g.priors(k) * naive_gaussian_pdf(x, g.means[static_cast<std::size_t>(k)],
                                          g.covariances[static_cast<std::size_t>(k)]);
  return p;
}

inline Eigen::MatrixXd random_spd(int d, mg::Rng& rng, double scale = 1.0) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd a(d, d);
  for (int i = 0; i < d; ++i)
    for (int j = 0; j < d; ++j) a(i, j) = normal(rng);
  Eigen::MatrixXd s = scale * (a * a.transpose() / d + 0.3 * Eigen::MatrixXd::Identity(d, d));
  return 0.5 * (s + s.transpose());
}

inline Gmm random_gmm(int k_count, int d, mg::Rng& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Gmm g;
  g.priors.resize(k_count);
  for (int k = 0; k < k_count; ++k) {
    g.priors(k) = 0.5 + std::abs(normal(rng));
    Eigen::VectorXd m(d);
    for (int i = 0; i < d; ++i) m(i) = 2.0 * normal(rng);
    g.means.push_back(m);
    g.covariances.push_back(random_spd(d, rng));
  }
  g.priors /= g.priors.sum();
  return g;
}

}  // namespace mg::stats::testing
