#include "stats/gpr.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "test_util.hpp"

namespace mg::stats {
namespace {

double se(double a, double b, double l, double sf) {
  return sf * sf * std::exp(-0.5 * (a - b) * (a - b) / (l * l));
}

GpHyperparameters hyper1(double l, double sf, double sn) {
  GpHyperparameters h;
  h.length_scales = Eigen::VectorXd::Constant(1, l);
  h.signal_std = sf;
  h.noise_std = sn;
  return h;
}

TEST(StatsGpr, GradientMatchesFiniteDifferences) {
  mg::Rng rng(41);
  for (int d : {1, 2, 3}) {
    const Eigen::MatrixXd x = Eigen::MatrixXd::Random(12, d) * 2.0;
    Eigen::VectorXd y(12);
    for (int i = 0; i < 12; ++i)
      y(i) = std::sin(x.row(i).sum()) + 0.1 * Eigen::VectorXd::Random(1)(0);
    for (int trial = 0; trial < 4; ++trial) {
      Eigen::VectorXd p = Eigen::VectorXd::Random(d + 2) * 0.8;
      p(d + 1) -= 1.5;  // moderate noise
      Eigen::VectorXd g;
      const double f = gp_log_marginal_likelihood(x, y, p, &g);
      ASSERT_TRUE(std::isfinite(f));
      for (int i = 0; i < d + 2; ++i) {
        const double h = 1e-6;
        Eigen::VectorXd pp = p, pm = p;
        pp(i) += h;
        pm(i) -= h;
        const double fd =
            (gp_log_marginal_likelihood(x, y, pp) - gp_log_marginal_likelihood(x, y, pm)) / (2 * h);
        EXPECT_NEAR(g(i), fd, 1e-5 * std::max(1.0, std::abs(fd))) << "d=" << d << " param " << i;
      }
    }
  }
}

TEST(StatsGpr, OnePointPosteriorByHand) {
  // With one point the centred target is 0, so the mean is the point's value everywhere and the
  // latent variance is sf^2 - k^2 / (sf^2 + sn^2).
  Eigen::MatrixXd x(1, 1);
  x << 0.5;
  const Eigen::VectorXd y = Eigen::VectorXd::Constant(1, 2.0);
  const GpModel m = make_gp_model(x, y, hyper1(0.7, 1.3, 0.2));
  const double xs = 1.1;
  const GpPrediction p = gp_predict(m, Eigen::VectorXd::Constant(1, xs));
  const double k = se(xs, 0.5, 0.7, 1.3);
  EXPECT_NEAR(p.mean, 2.0, 1e-12);
  EXPECT_NEAR(p.latent_variance, 1.69 - k * k / (1.69 + 0.04), 1e-12);
  EXPECT_NEAR(p.noise_variance, 0.04, 1e-12);
  EXPECT_NEAR(m.log_marginal_likelihood,
              -0.5 * std::log(1.69 + 0.04) - 0.5 * std::log(2 * std::numbers::pi), 1e-12);
}

TEST(StatsGpr, TwoPointPosteriorByHand) {
  const double x1 = -0.3, x2 = 0.4, y1 = 1.0, y2 = 3.0, l = 0.5, sf = 2.0, sn = 0.3;
  Eigen::MatrixXd x(2, 1);
  x << x1, x2;
  const GpModel m = make_gp_model(x, Eigen::Vector2d(y1, y2), hyper1(l, sf, sn));
  const double mu = 2.0;  // prior mean = training mean
  const double a = sf * sf + sn * sn, c = se(x1, x2, l, sf), det = a * a - c * c;
  // (K + sn^2 I)^-1 = [a -c; -c a] / det
  for (double xs : {-1.0, 0.0, 0.2, 3.0}) {
    const double k1 = se(xs, x1, l, sf), k2 = se(xs, x2, l, sf);
    const double r1 = y1 - mu, r2 = y2 - mu;
    const double mean = mu + (k1 * (a * r1 - c * r2) + k2 * (-c * r1 + a * r2)) / det;
    const double var = sf * sf - (k1 * (a * k1 - c * k2) + k2 * (-c * k1 + a * k2)) / det;
    const GpPrediction p = gp_predict(m, Eigen::VectorXd::Constant(1, xs));
    EXPECT_NEAR(p.mean, mean, 1e-12) << xs;
    EXPECT_NEAR(p.latent_variance, var, 1e-12) << xs;
  }
  const double quad =
      ((y1 - mu) * (a * (y1 - mu) - c * (y2 - mu)) + (y2 - mu) * (-c * (y1 - mu) + a * (y2 - mu))) /
      det;
  EXPECT_NEAR(m.log_marginal_likelihood,
              -0.5 * quad - 0.5 * std::log(det) - std::log(2 * std::numbers::pi), 1e-12);
}

TEST(StatsGpr, ThreePointsTwoDimensionsByTextbookFormula) {
  Eigen::MatrixXd x(3, 2);
  x << 0.0, 0.0, 1.0, 0.5, -0.5, 1.5;
  const Eigen::Vector3d y(0.2, -0.4, 1.1);
  GpHyperparameters h;
  h.length_scales = Eigen::Vector2d(0.8, 1.7);
  h.signal_std = 0.9;
  h.noise_std = 0.05;
  const GpModel m = make_gp_model(x, y, h);
  auto k = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d d = (a - b).cwiseQuotient(h.length_scales);
    return 0.81 * std::exp(-0.5 * d.squaredNorm());
  };
  Eigen::Matrix3d kk;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) kk(i, j) = k(x.row(i), x.row(j)) + (i == j ? 0.0025 : 0.0);
  const Eigen::Vector2d xs(0.3, 0.8);
  Eigen::Vector3d ks;
  for (int i = 0; i < 3; ++i) ks(i) = k(xs, x.row(i));
  const double mu = y.mean();
  const Eigen::Matrix3d inv = kk.inverse();
  const GpPrediction p = gp_predict(m, xs);
  EXPECT_NEAR(p.mean, mu + ks.dot(inv * (y.array() - mu).matrix()), 1e-10);
  EXPECT_NEAR(p.latent_variance, 0.81 - ks.dot(inv * ks), 1e-10);
}

TEST(StatsGpr, FarFromDataRevertsToThePriorMean) {
  mg::Rng rng(42);
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(15, 2);
  Eigen::VectorXd y(15);
  for (int i = 0; i < 15; ++i) y(i) = 3.0 + 2.0 * x(i, 0) - x(i, 1);
  const GpModel m = fit_gpr(x, y, rng);
  for (double r : {1e3, 1e6, 1e200}) {
    const GpPrediction p = gp_predict(m, Eigen::Vector2d(r, -r));
    ASSERT_TRUE(std::isfinite(p.mean) && std::isfinite(p.variance()));
    EXPECT_NEAR(p.mean, y.mean(), 1e-9);
    EXPECT_NEAR(p.latent_variance, m.hyper.signal_std * m.hyper.signal_std, 1e-9);
  }
  // ...while near the data it follows the data, not the prior mean.
  const GpPrediction near = gp_predict(m, Eigen::Vector2d(0.5, 0.5));
  EXPECT_NEAR(near.mean, 3.5, 0.1);
}

TEST(StatsGpr, RecoversALinearMapFromFewNoisyPoints) {
  for (int n : {5, 12, 30}) {
    mg::Rng rng(43 + n);
    std::normal_distribution<double> noise(0.0, 0.02);
    const Eigen::MatrixXd x = Eigen::MatrixXd::Random(n, 2);
    Eigen::VectorXd y(n);
    for (int i = 0; i < n; ++i) y(i) = 0.5 + 1.5 * x(i, 0) - 0.8 * x(i, 1) + noise(rng);
    const GpModel m = fit_gpr(x, y, rng);
    double mse = 0.0;
    const Eigen::MatrixXd q = Eigen::MatrixXd::Random(100, 2) * 0.8;
    for (int i = 0; i < 100; ++i) {
      const double truth = 0.5 + 1.5 * q(i, 0) - 0.8 * q(i, 1);
      mse += std::pow(gp_predict(m, q.row(i).transpose()).mean - truth, 2) / 100.0;
    }
    EXPECT_LT(mse, n >= 12 ? 2e-3 : 0.05) << "n = " << n;
  }
}

TEST(StatsGpr, MoreRestartsNeverFindAWorseOptimumAndSeedsAreDeterministic) {
  mg::Rng data_rng(44);
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(20, 1) * 3.0;
  Eigen::VectorXd y(20);
  std::normal_distribution<double> noise(0.0, 0.3);
  for (int i = 0; i < 20; ++i) y(i) = std::sin(3.0 * x(i, 0)) + noise(data_rng);
  GprOptions one;
  one.restarts = 1;
  GprOptions many;
  many.restarts = 10;
  mg::Rng r1(1), r2(1), r3(1);
  const GpModel a = fit_gpr(x, y, r1, one);
  const GpModel b = fit_gpr(x, y, r2, many);
  const GpModel c = fit_gpr(x, y, r3, many);
  EXPECT_GE(b.log_marginal_likelihood, a.log_marginal_likelihood - 1e-9);
  EXPECT_EQ(b.log_marginal_likelihood, c.log_marginal_likelihood);
  EXPECT_EQ(b.hyper.length_scales, c.hyper.length_scales);
  // At the optimum (inside the bounds) the gradient vanishes.
  Eigen::VectorXd p(3), g;
  p << std::log(b.hyper.length_scales(0)), std::log(b.hyper.signal_std / b.output_scale),
      std::log(b.hyper.noise_std / b.output_scale);
  gp_log_marginal_likelihood(x, (y.array() - b.output_mean) / b.output_scale, p, &g);
  EXPECT_LT(g.cwiseAbs().maxCoeff(), 1e-3) << g.transpose();
}

TEST(StatsGpr, UserBoundsAndInitialGuessAreHonoured) {
  mg::Rng rng(45);
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(10, 1);
  Eigen::VectorXd y = x.col(0) * 2.0;
  GprOptions opt;
  opt.noise_std_bounds = {0.3, 0.5};
  opt.length_scale_bounds = {0.05, 0.1};
  const GpModel m = fit_gpr(x, y, rng, opt);
  EXPECT_GE(m.hyper.noise_std, 0.3 * (1 - 1e-12));
  EXPECT_LE(m.hyper.noise_std, 0.5 * (1 + 1e-12));
  EXPECT_LE(m.hyper.length_scales(0), 0.1 * (1 + 1e-12));
  GprOptions fixed;
  fixed.optimize = false;
  fixed.initial_length_scales = Eigen::VectorXd::Constant(1, 0.42);
  fixed.initial_signal_std = 1.5;
  fixed.initial_noise_std = 0.07;
  const GpModel f = fit_gpr(x, y, rng, fixed);
  EXPECT_NEAR(f.hyper.length_scales(0), 0.42, 1e-12);
  EXPECT_NEAR(f.hyper.signal_std, 1.5, 1e-12);
  EXPECT_NEAR(f.hyper.noise_std, 0.07, 1e-12);
  GprOptions bad;
  bad.noise_std_bounds = {0.5, 0.1};
  EXPECT_THROW(fit_gpr(x, y, rng, bad), InputError);
  bad = {};
  bad.restarts = 0;
  EXPECT_THROW(fit_gpr(x, y, rng, bad), InputError);
}

TEST(StatsGpr, DuplicatePointsAndConstantColumnsStayFinite) {
  Eigen::MatrixXd x(4, 2);
  x << 0.0, 7.0, 0.0, 7.0, 1.0, 7.0, 1.0, 7.0;  // duplicated rows, constant second column
  const Eigen::Vector4d y(1.0, 1.1, 2.0, 2.1);
  const GpModel exact = make_gp_model(x, y, GpHyperparameters{Eigen::Vector2d(1.0, 1.0), 1.0, 0.0});
  EXPECT_GT(exact.jitter, 0.0);  // singular without jitter
  EXPECT_TRUE(std::isfinite(gp_predict(exact, Eigen::Vector2d(0.5, 7.0)).mean));
  mg::Rng rng(46);
  const GpModel m = fit_gpr(x, y, rng);
  const GpPrediction p = gp_predict(m, Eigen::Vector2d(0.5, 3.0));
  EXPECT_TRUE(std::isfinite(p.mean) && std::isfinite(p.variance()) && p.variance() > 0.0);
}

TEST(StatsGpr, RejectsBadInput) {
  Eigen::MatrixXd x = Eigen::MatrixXd::Random(3, 1);
  EXPECT_THROW(make_gp_model(x, Eigen::Vector2d(1, 2), hyper1(1, 1, 0.1)), InputError);
  EXPECT_THROW(make_gp_model(x, Eigen::Vector3d(1, 2, 3), hyper1(-1, 1, 0.1)), InputError);
  x(1, 0) = std::nan("");
  mg::Rng rng(47);
  EXPECT_THROW(fit_gpr(x, Eigen::Vector3d(1, 2, 3), rng), InputError);
  EXPECT_THROW(gp_predict(make_gp_model(Eigen::MatrixXd::Ones(2, 1), Eigen::Vector2d(1, 2),
                                        hyper1(1, 1, 0.1)),
                          Eigen::Vector2d(0, 0)),
               InputError);
}

}  // namespace
}  // namespace mg::stats
