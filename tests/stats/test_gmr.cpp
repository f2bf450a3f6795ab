#include "stats/gmr.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "test_util.hpp"

namespace mg::stats {
namespace {

using testing::naive_gaussian_pdf;

Eigen::MatrixXd pick(const Eigen::MatrixXd& m, const std::vector<int>& r,
                     const std::vector<int>& c) {
  Eigen::MatrixXd out(r.size(), c.size());
  for (std::size_t i = 0; i < r.size(); ++i)
    for (std::size_t j = 0; j < c.size(); ++j) out(i, j) = m(r[i], c[j]);
  return out;
}
Eigen::VectorXd pick(const Eigen::VectorXd& v, const std::vector<int>& r) {
  Eigen::VectorXd out(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) out(i) = v(r[i]);
  return out;
}

// Conditioning through the precision matrix Lambda = Sigma^-1 (an independent route from the
// Schur-complement form): Sigma_O|I = Lambda_OO^-1, mu_O|I = mu_O - Lambda_OO^-1 Lambda_OI (x -
// mu_I).
GmrPrediction condition_by_precision(const Eigen::VectorXd& mean, const Eigen::MatrixXd& cov,
                                     const std::vector<int>& in, const std::vector<int>& out,
                                     const Eigen::VectorXd& x) {
  std::vector<int> keep = in;
  keep.insert(keep.end(), out.begin(), out.end());
  const Eigen::MatrixXd marginal = pick(cov, keep, keep);  // marginalise the unused dims first
  const Eigen::MatrixXd lambda = marginal.inverse();
  const int ni = static_cast<int>(in.size());
  const int no = static_cast<int>(out.size());
  const Eigen::MatrixXd l_oo = lambda.bottomRightCorner(no, no);
  const Eigen::MatrixXd l_oi = lambda.bottomLeftCorner(no, ni);
  GmrPrediction p;
  p.covariance = l_oo.inverse();
  p.mean = pick(mean, out) - p.covariance * l_oi * (x - pick(mean, in));
  return p;
}

TEST(StatsGmr, SingleGaussianMatchesPrecisionRoute) {
  mg::Rng rng(11);
  const Gmm g = testing::random_gmm(1, 5, rng);
  const std::vector<int> in{3, 0}, out{4, 1};  // unordered subsets, dim 2 marginalised
  const Eigen::Vector2d x(0.7, -1.2);
  const GmrPrediction p = gmr_predict(g, in, out, x);
  const GmrPrediction ref = condition_by_precision(g.means[0], g.covariances[0], in, out, x);
  EXPECT_TRUE(p.mean.isApprox(ref.mean, 1e-10))
      << p.mean.transpose() << " vs " << ref.mean.transpose();
  EXPECT_TRUE(p.covariance.isApprox(ref.covariance, 1e-10));
}

TEST(StatsGmr, MixtureMatchesBruteForce) {
  mg::Rng rng(12);
  const Gmm g = testing::random_gmm(3, 4, rng);
  const std::vector<int> in{0, 2}, out{1, 3};
  const Eigen::Vector2d x(0.3, 0.9);
  // Weights from the textbook marginal density; moments E[y] and E[y y^T] of the mixture.
  Eigen::VectorXd w(3);
  std::vector<GmrPrediction> parts;
  for (int k = 0; k < 3; ++k) {
    w(k) =
        g.priors(k) * naive_gaussian_pdf(x, pick(g.means[k], in), pick(g.covariances[k], in, in));
    parts.push_back(condition_by_precision(g.means[k], g.covariances[k], in, out, x));
  }
  w /= w.sum();
  Eigen::Vector2d m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
  for (int k = 0; k < 3; ++k) {
    m += w(k) * parts[k].mean;
    second += w(k) * (parts[k].covariance + parts[k].mean * parts[k].mean.transpose());
  }
  const Eigen::Matrix2d cov = second - m * m.transpose();
  const GmrPrediction p = gmr_predict(g, in, out, x);
  EXPECT_TRUE(p.mean.isApprox(m, 1e-9));
  EXPECT_TRUE(p.covariance.isApprox(cov, 1e-9));
}

TEST(StatsGmr, OneDimensionalMixtureMatchesNumericalIntegration) {
  mg::Rng rng(13);
  const Gmm g = testing::random_gmm(3, 2, rng);
  const GmrConditioner cond(g, {0}, {1});
  for (double xq : {-2.0, 0.0, 1.5}) {
    // p(y | x) proportional to the joint density on a fine grid over y.
    double z = 0.0, s1 = 0.0, s2 = 0.0;
    const double lo = -15.0, hi = 15.0,
                 dy = 5e-3;  // Riemann sums of smooth, decaying densities converge fast
    for (double y = lo; y <= hi; y += dy) {
      const double p = testing::naive_gmm_pdf(g, Eigen::Vector2d(xq, y));
      z += p;
      s1 += p * y;
      s2 += p * y * y;
    }
    const double mean = s1 / z;
    const double var = s2 / z - mean * mean;
    const GmrPrediction p = cond.predict(Eigen::VectorXd::Constant(1, xq));
    EXPECT_NEAR(p.mean(0), mean, 1e-6) << "x = " << xq;
    EXPECT_NEAR(p.covariance(0, 0), var, 1e-6) << "x = " << xq;
  }
}

TEST(StatsGmr, FarFromDataFollowsTheDominantComponentsTrend) {
  // Two components along a line with different slopes; far to the right the right-hand component's
  // linear trend continues (thesis 3.4.1), and nothing is NaN even where every density underflows.
  Gmm g;
  g.priors = Eigen::Vector2d(0.5, 0.5);
  g.means = {Eigen::Vector2d(-2.0, -2.0), Eigen::Vector2d(2.0, 4.0)};
  Eigen::Matrix2d c1, c2;
  c1 << 1.0, 1.0, 1.0, 1.1;  // slope 1
  c2 << 1.0, 3.0, 3.0, 9.1;  // slope 3
  g.covariances = {c1, c2};
  const GmrConditioner cond(g, {0}, {1});
  for (double xq : {50.0, 1e3, 1e6}) {
    const GmrPrediction p = cond.predict(Eigen::VectorXd::Constant(1, xq));
    ASSERT_TRUE(p.mean.allFinite() && p.covariance.allFinite());
    EXPECT_NEAR(p.mean(0), 4.0 + 3.0 * (xq - 2.0), 1e-9 * std::abs(xq) + 1e-9);
    EXPECT_NEAR(p.covariance(0, 0), 0.1, 1e-9);
  }
  const GmrPrediction left = cond.predict(Eigen::VectorXd::Constant(1, -1e3));
  EXPECT_NEAR(left.mean(0), -2.0 + 1.0 * (-1e3 + 2.0), 1e-6);
}

TEST(StatsGmr, ConditionerWorkspaceMatchesOneShot) {
  mg::Rng rng(14);
  const Gmm g = testing::random_gmm(4, 3, rng);
  const GmrConditioner cond(g, {0, 1}, {2});
  auto ws = cond.make_workspace();
  Eigen::VectorXd mean(1);
  Eigen::MatrixXd cov(1, 1);
  Eigen::VectorXd h(4);
  for (int i = 0; i < 10; ++i) {
    const Eigen::Vector2d x = Eigen::Vector2d::Random() * 3.0;
    const GmrPrediction ref = gmr_predict(g, {0, 1}, {2}, x);
    cond.predict_mean(x, mean, ws);
    EXPECT_NEAR(mean(0), ref.mean(0), 1e-12);
    cond.predict(x, mean, cov, ws);
    EXPECT_NEAR(cov(0, 0), ref.covariance(0, 0), 1e-12);
    cond.responsibilities(x, h, ws);
    EXPECT_NEAR(h.sum(), 1.0, 1e-12);
    EXPECT_TRUE(cond.gain(0).allFinite());
  }
}

TEST(StatsGmr, EmptyInputGivesTheMarginal) {
  mg::Rng rng(15);
  const Gmm g = testing::random_gmm(2, 2, rng);
  const GmrPrediction p = gmr_predict(g, {}, {1}, Eigen::VectorXd(0));
  const double m = g.priors(0) * g.means[0](1) + g.priors(1) * g.means[1](1);
  EXPECT_NEAR(p.mean(0), m, 1e-12);
}

TEST(StatsGmr, RejectsBadDimensions) {
  mg::Rng rng(16);
  const Gmm g = testing::random_gmm(2, 3, rng);
  EXPECT_THROW(GmrConditioner(g, {0, 0}, {1}), InputError);
  EXPECT_THROW(GmrConditioner(g, {0}, {0}), InputError);
  EXPECT_THROW(GmrConditioner(g, {0}, {3}), InputError);
  EXPECT_THROW(GmrConditioner(g, {0}, {}), InputError);
  EXPECT_THROW(gmr_predict(g, {0}, {1}, Eigen::Vector2d::Zero()), InputError);
}

}  // namespace
}  // namespace mg::stats
