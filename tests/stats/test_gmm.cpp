#include "stats/gmm.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "test_util.hpp"

namespace mg::stats {
namespace {

using testing::naive_gmm_pdf;
using testing::sample_gaussian;

Eigen::MatrixXd two_clusters(int n_each, mg::Rng& rng) {
  Eigen::Matrix2d c1;
  c1 << 0.3, 0.1, 0.1, 0.2;
  Eigen::Matrix2d c2;
  c2 << 0.2, -0.05, -0.05, 0.4;
  Eigen::MatrixXd data(2 * n_each, 2);
  data.topRows(n_each) = sample_gaussian(Eigen::Vector2d(-3.0, 0.0), c1, n_each, rng);
  data.bottomRows(n_each) = sample_gaussian(Eigen::Vector2d(3.0, 1.0), c2, n_each, rng);
  return data;
}

TEST(StatsGmm, LogLikelihoodMatchesTextbookDensity) {
  mg::Rng rng(1);
  const Gmm g = testing::random_gmm(3, 3, rng);
  const Eigen::MatrixXd x =
      sample_gaussian(Eigen::VectorXd::Zero(3), Eigen::MatrixXd::Identity(3, 3) * 4.0, 20, rng);
  double expected = 0.0;
  for (int i = 0; i < x.rows(); ++i) expected += std::log(naive_gmm_pdf(g, x.row(i).transpose()));
  EXPECT_NEAR(gmm_log_likelihood(g, x), expected, 1e-9 * std::abs(expected));
}

TEST(StatsGmm, LogLikelihoodFiniteFarFromAllComponents) {
  mg::Rng rng(2);
  const Gmm g = testing::random_gmm(2, 2, rng);
  const Eigen::Vector2d far(1e4, -1e4);
  const double ll = gmm_log_density(g, far);
  EXPECT_TRUE(std::isfinite(ll));
  EXPECT_LT(ll, -1e5);
  const Eigen::MatrixXd r = gmm_responsibilities(g, far.transpose());
  EXPECT_TRUE(r.allFinite());
  EXPECT_NEAR(r.sum(), 1.0, 1e-12);
}

TEST(StatsGmm, EmNeverDecreasesTheLikelihood) {
  for (double reg : {0.0, 1e-6}) {
    mg::Rng rng(3);
    const Eigen::MatrixXd data = two_clusters(60, rng);
    EmOptions opt;
    opt.reg_covar = reg;
    opt.tolerance = 1e-14;  // run many iterations
    opt.max_iterations = 200;
    const EmResult r = fit_gmm(data, 4, rng, opt);
    ASSERT_GE(r.log_likelihood_trace.size(), 3u);
    for (std::size_t i = 1; i < r.log_likelihood_trace.size(); ++i) {
      const double prev = r.log_likelihood_trace[i - 1];
      EXPECT_GE(r.log_likelihood_trace[i], prev - 1e-9 * std::abs(prev))
          << "step " << i << " reg " << reg;
    }
    EXPECT_DOUBLE_EQ(r.log_likelihood, r.log_likelihood_trace.back());
    EXPECT_NEAR(r.log_likelihood, gmm_log_likelihood(r.gmm, data),
                1e-9 * std::abs(r.log_likelihood));
  }
}

TEST(StatsGmm, RecoversTwoWellSeparatedClusters) {
  mg::Rng rng(4);
  const Eigen::MatrixXd data = two_clusters(500, rng);
  const EmResult r = fit_gmm(data, 2, rng);
  r.gmm.validate();
  const int left = r.gmm.means[0](0) < r.gmm.means[1](0) ? 0 : 1;
  const auto& ml = r.gmm.means[static_cast<std::size_t>(left)];
  const auto& mr = r.gmm.means[static_cast<std::size_t>(1 - left)];
  EXPECT_NEAR(ml(0), -3.0, 0.1);
  EXPECT_NEAR(ml(1), 0.0, 0.1);
  EXPECT_NEAR(mr(0), 3.0, 0.1);
  EXPECT_NEAR(mr(1), 1.0, 0.1);
  EXPECT_NEAR(r.gmm.priors(0), 0.5, 0.02);
  EXPECT_NEAR(r.gmm.covariances[static_cast<std::size_t>(left)](0, 1), 0.1, 0.05);
  EXPECT_NEAR(r.gmm.covariances[static_cast<std::size_t>(1 - left)](1, 1), 0.4, 0.08);
}

TEST(StatsGmm, SameSeedSameBits) {
  mg::Rng data_rng(5);
  const Eigen::MatrixXd data = two_clusters(40, data_rng);
  mg::Rng a(77), b(77);
  const EmResult ra = fit_gmm(data, 3, a);
  const EmResult rb = fit_gmm(data, 3, b);
  EXPECT_EQ(ra.log_likelihood, rb.log_likelihood);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(ra.gmm.means[static_cast<std::size_t>(k)], rb.gmm.means[static_cast<std::size_t>(k)]);
    EXPECT_EQ(ra.gmm.covariances[static_cast<std::size_t>(k)],
              rb.gmm.covariances[static_cast<std::size_t>(k)]);
  }
}

TEST(StatsGmm, BicPicksTheTrueNumberOfClusters) {
  mg::Rng rng(6);
  const Eigen::MatrixXd two = two_clusters(100, rng);
  EXPECT_EQ(fit_gmm_bic(two, 4, rng).gmm.num_components(), 2);
  const Eigen::MatrixXd one =
      sample_gaussian(Eigen::Vector2d(1.0, 2.0), Eigen::Matrix2d::Identity(), 200, rng);
  EXPECT_EQ(fit_gmm_bic(one, 4, rng).gmm.num_components(), 1);
  EXPECT_EQ(gmm_num_parameters(2, 3), 1 + 6 + 12);
}

TEST(StatsGmm, ConstantColumnAndDuplicatePointsStayFinite) {
  Eigen::MatrixXd data(6, 3);
  data << 0, 1, 5, 0, 1, 5, 1, 2, 5, 1, 2, 5, 2, 3, 5, 2, 3,
      5;  // third column constant, rows duplicated
  mg::Rng rng(7);
  const EmResult r = fit_gmm(data, 3, rng);
  EXPECT_TRUE(std::isfinite(r.log_likelihood));
  EXPECT_NO_THROW(r.gmm.validate());
}

TEST(StatsGmm, KMeansSeparatesClusters) {
  mg::Rng rng(8);
  const Eigen::MatrixXd data = two_clusters(50, rng);
  const KMeansResult km = kmeans(data, 2, rng);
  for (int i = 1; i < 50; ++i) EXPECT_EQ(km.labels[static_cast<std::size_t>(i)], km.labels[0]);
  for (int i = 51; i < 100; ++i) EXPECT_EQ(km.labels[static_cast<std::size_t>(i)], km.labels[50]);
  EXPECT_NE(km.labels[0], km.labels[50]);
}

TEST(StatsGmm, RejectsBadInput) {
  mg::Rng rng(9);
  Eigen::MatrixXd data = Eigen::MatrixXd::Random(5, 2);
  EXPECT_THROW(fit_gmm(data, 6, rng), InputError);
  EXPECT_THROW(fit_gmm(data, 0, rng), InputError);
  data(2, 1) = std::nan("");
  EXPECT_THROW(fit_gmm(data, 2, rng), InputError);
  EmOptions bad;
  bad.reg_covar = -1.0;
  EXPECT_THROW(fit_gmm(Eigen::MatrixXd::Random(5, 2), 2, rng, bad), InputError);
}

TEST(StatsGmm, ValidateNamesTheProblem) {
  mg::Rng rng(10);
  Gmm g = testing::random_gmm(2, 2, rng);
  EXPECT_NO_THROW(g.validate());
  Gmm bad_prior = g;
  bad_prior.priors(0) += 0.1;
  EXPECT_THROW(bad_prior.validate(), InputError);
  Gmm not_pd = g;
  not_pd.covariances[1](0, 0) = -1.0;
  try {
    not_pd.validate();
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("component 1"), std::string::npos) << e.what();
  }
  Gmm wrong_dim = g;
  wrong_dim.means[0] = Eigen::Vector3d::Zero();
  EXPECT_THROW(wrong_dim.validate(), InputError);
}

// Every k-means restart with a non-finite inertia used to return an empty clustering that EM read
// out of bounds (SIGSEGV); now it is a NumericalError.
TEST(StatsGmm, OverflowingDataIsAnErrorNotACrash) {
  Eigen::MatrixXd data(3, 1);
  data << 1e200, 2.0, -1e200;
  mg::Rng rng(1);
  EXPECT_THROW(kmeans(data, 1, rng), mg::NumericalError);
  EXPECT_THROW(fit_gmm(data, 1, rng), mg::Error);
}

}  // namespace
}  // namespace mg::stats
