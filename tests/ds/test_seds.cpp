#include "ds/seds.hpp"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "ds/demonstrations.hpp"
#include "ds/hitting_model.hpp"
#include "seds_test_util.hpp"
#include "stats/gmr.hpp"

namespace mg::ds {
namespace {

using testing::demo_data;

std::vector<SedsComponent> random_components(int k, Rng& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<SedsComponent> out(static_cast<std::size_t>(k));
  for (auto& c : out) {
    c.prior = 0.2 + std::abs(n(rng));
    c.mu = Eigen::Vector3d(-0.2 + 0.1 * n(rng), 0.03 * n(rng), 0.05 + 0.03 * n(rng));
    Eigen::Matrix3d l = Eigen::Matrix3d::Zero();
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s <= r; ++s) l(r, s) = (r == s ? 0.08 : 0.02 * n(rng));
    c.sigma = l * l.transpose();
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) c.a(r, s) = (r == s ? -4.0 : 0.0) + n(rng);
    l.setZero();
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s <= r; ++s) l(r, s) = (r == s ? 0.3 : 0.05 * n(rng));
    c.c = l * l.transpose();
  }
  return out;
}

class SedsGradient : public ::testing::TestWithParam<SedsObjective> {};

TEST_P(SedsGradient, AnalyticGradientMatchesFiniteDifferences) {
  const SedsObjective obj = GetParam();
  Rng rng(11);
  const auto comps = random_components(3, rng);
  const SedsData data = demo_data(2, 5);
  const double floor = 1e-6;
  const Eigen::VectorXd p = pack_seds(comps, obj, floor);
  Eigen::VectorXd g;
  const double f0 = seds_objective(p, data, obj, floor, comps, &g);
  ASSERT_TRUE(std::isfinite(f0));
  ASSERT_EQ(g.size(), p.size());
  double worst = 0.0;
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    const double h = 1e-6 * std::max(1.0, std::abs(p[i]));
    Eigen::VectorXd pp = p, pm = p;
    pp[i] += h;
    pm[i] -= h;
    const double fd = (seds_objective(pp, data, obj, floor, comps, nullptr) -
                       seds_objective(pm, data, obj, floor, comps, nullptr)) /
                      (2 * h);
    const double err = std::abs(fd - g[i]) / std::max(1.0, std::abs(fd));
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-5) << "parameter " << i << " analytic " << g[i] << " fd " << fd;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", worst);
  RecordProperty("worst_relative_gradient_error", buf);
}

INSTANTIATE_TEST_SUITE_P(Objectives, SedsGradient,
                         ::testing::Values(SedsObjective::kLikelihood, SedsObjective::kMse));

TEST(Seds, PackUnpackRoundTrip) {
  Rng rng(2);
  const auto comps = random_components(2, rng);
  const auto back = unpack_seds(pack_seds(comps, SedsObjective::kLikelihood, 1e-6),
                                SedsObjective::kLikelihood, 1e-6, comps);
  ASSERT_EQ(back.size(), comps.size());
  double total = 0.0;
  for (const auto& c : comps) total += c.prior;
  for (std::size_t k = 0; k < comps.size(); ++k) {
    EXPECT_NEAR(back[k].prior, comps[k].prior / total, 1e-12);
    EXPECT_TRUE(back[k].sigma.isApprox(comps[k].sigma, 1e-9));
    EXPECT_TRUE(back[k].a.isApprox(comps[k].a, 1e-12));
    EXPECT_TRUE(back[k].c.isApprox(comps[k].c, 1e-9));
  }
}

TEST(Seds, JointGmmFormIsEquivalent) {
  Rng rng(3);
  const auto comps = random_components(3, rng);
  const stats::Gmm gmm = seds_to_gmm(comps);
  const auto back = seds_from_gmm(gmm);
  for (std::size_t k = 0; k < comps.size(); ++k) EXPECT_TRUE(back[k].a.isApprox(comps[k].a, 1e-9));
  double bias = 1.0;
  seds_check(gmm, &bias);
  EXPECT_LT(bias, 1e-9);
  // GMR through mg::stats agrees with the direct SEDS formula.
  const stats::GmrConditioner gmr(gmm, {0, 1, 2}, {3, 4, 5});
  for (const Eigen::Vector3d& y :
       {Eigen::Vector3d(-0.3, 0.05, 0.1), Eigen::Vector3d(0.01, -0.02, 0.0)}) {
    const Eigen::VectorXd a = gmr.predict(Eigen::VectorXd(y)).mean;
    EXPECT_LT((a - seds_velocity(comps, y)).norm(), 1e-9);
  }
}

TEST(Seds, GmrStaysFiniteFarFromAllComponents) {
  Rng rng(4);
  const auto comps = random_components(3, rng);
  const stats::Gmm gmm = seds_to_gmm(comps);
  const stats::GmrConditioner gmr(gmm, {0, 1, 2}, {3, 4, 5});
  for (const double s : {1.0, 1e2, 1e4, 1e6}) {
    for (const Eigen::Vector3d& dir :
         {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 2, 3), Eigen::Vector3d(0, 0, -1)}) {
      const Eigen::Vector3d y = s * dir;
      EXPECT_TRUE(seds_velocity(comps, y).allFinite()) << s;
      EXPECT_TRUE(gmr.predict(Eigen::VectorXd(y)).mean.allFinite()) << s;
    }
  }
}

TEST(Seds, BadInputIsAClearError) {
  SedsData empty;
  empty.y.resize(3, 0);
  empty.ydot.resize(3, 0);
  SedsOptions opt;
  EXPECT_THROW(fit_seds(empty, opt), InputError);
  SedsData data = demo_data(1, 1);
  data.ydot(0, 3) = std::nan("");
  EXPECT_THROW(fit_seds(data, opt), InputError);
  opt.gaussians = 0;
  EXPECT_THROW(fit_seds(demo_data(1, 1), opt), InputError);
  EXPECT_THROW(parse_seds_objective("bogus"), InputError);
}

TEST(Seds, UnstableGmmIsRejectedByTheModel) {
  Rng rng(8);
  auto comps = random_components(2, rng);
  comps[1].a = Eigen::Matrix3d::Identity();  // expanding: violates A + A^T < 0
  stats::Gmm strength;
  strength.priors = Eigen::VectorXd::Ones(1);
  strength.means = {Eigen::Vector4d(0, 0, 0, 1.5)};
  strength.covariances = {Eigen::Matrix4d::Identity() * 0.01};
  EXPECT_THROW(HittingModel(seds_to_gmm(comps), strength, Eigen::Vector3d(0, 0, kBallRadius),
                            Eigen::Vector3d::UnitX(), {}),
               NumericalError);
}

}  // namespace
}  // namespace mg::ds
