#include "learning/learner.hpp"

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "learning_test_util.hpp"

namespace mg::learning {
namespace {

using testing::flat_field;
using testing::linear_map;
using testing::options;
using testing::same_bits;

TEST(LearningModel, FlatFieldLawIsRecoveredFromFewNoisyPoints) {
  // theta = atan2(xi_y, xi_x) and a sqrt-of-distance speed from 5-30 noisy examples. The bounds
  // are fractions of each output's variance over the validation set (1 - R^2): GPR fits the
  // smooth law closely, GMR with 2 Gaussians is a coarser piecewise-linear approximation.
  const Dataset val = flat_field(300, 999, 0.0);
  Eigen::Vector2d variance;
  for (int o = 0; o < 2; ++o)
    variance(o) = (val.outputs.col(o).array() - val.outputs.col(o).mean()).square().mean();
  for (int n : {5, 15, 30}) {
    const Dataset train_set = flat_field(n, 100 + n, 0.01);
    for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr}) {
      const Model model = train(train_set, options(m, m == Method::kGpr ? 0 : 2));
      const std::vector<Score> s = score(model, val);
      const double fraction = n == 5 ? 0.5 : m == Method::kGpr ? 0.02 : 0.25;
      for (int o = 0; o < 2; ++o) {
        EXPECT_LT(s[o].mse, fraction * variance(o))
            << method_name(m) << " n=" << n << " output " << o;
        EXPECT_TRUE(std::isfinite(s[o].nlpd));
      }
    }
  }
}

TEST(LearningModel, LinearMapIsRecovered) {
  const Dataset train_set = linear_map(20, 3, 0.01);
  const Dataset val = linear_map(200, 4, 0.0);
  for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr}) {
    const Model model = train(train_set, options(m, 1));
    const std::vector<Score> s = score(model, val);
    EXPECT_LT(s[0].mse, 1e-3) << method_name(m);
    EXPECT_LT(s[1].mse, 1e-3) << method_name(m);
  }
}

TEST(LearningModel, FarFromTheDataGprRevertsToTheMeanAndGmrContinuesTheTrend) {
  // Thesis 3.4.1 / figure 3.4.
  const Dataset train_set = linear_map(25, 5, 0.01);
  // Far means many length scales away: a linear map gets long length scales (up to 100 times
  // the inputs' std by default), so go 1000 half-widths out.
  Eigen::MatrixXd far(1, 2);
  far << 1000.0, 0.0;
  const Model gpr_model = train(train_set, options(Method::kGpr));
  ASSERT_LT(gpr_model.reports[0].length_scales(0), 100.0);
  const Predictions gpr = predict(gpr_model, far);
  EXPECT_NEAR(gpr.mean(0, 0), train_set.outputs.col(0).mean(), 1e-6);
  EXPECT_NEAR(gpr.mean(0, 1), train_set.outputs.col(1).mean(), 1e-6);
  for (double x : {8.0, 1000.0}) {
    far << x, 0.0;
    const double trend = 0.3 + 0.8 * x;
    for (Method m : {Method::kGmr, Method::kJointGmr}) {
      const Predictions gmr = predict(train(train_set, options(m, 2)), far);
      EXPECT_NEAR(gmr.mean(0, 0), trend, 0.05 * trend) << method_name(m) << " x=" << x;
      EXPECT_TRUE(gmr.std.allFinite());
    }
  }
  // Never NaN, however far.
  far << 1e150, -1e150;
  for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr}) {
    const Predictions p = predict(train(train_set, options(m, 2)), far);
    EXPECT_TRUE(p.mean.allFinite() && p.std.allFinite()) << method_name(m);
  }
}

// A GPR fit's cost grows as N^3 (1,500 rows ran over 150 s): larger sets are refused
// at once with a message that says why and what to use instead.
TEST(LearningModel, GprRefusesMoreRowsThanItsBoundAtOnce) {
  const Dataset big = linear_map(kMaxGprRows + 1, 9, 0.01);
  try {
    train(big, options(Method::kGpr));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(std::to_string(kMaxGprRows)), std::string::npos) << what;
    EXPECT_NE(what.find("gmr"), std::string::npos) << what;
  }
  // GMR takes the same rows.
  EXPECT_NO_THROW(train(big, options(Method::kGmr, 2)));
}

// reg_covar 0 would let a component collapse; the fit refuses it instead of writing a model that
// load_model then rejects.
TEST(LearningModel, ZeroRegCovarIsAnInputError) {
  TrainOptions o = options(Method::kGmr, 2);
  o.choose_reg_covar = false;
  o.em.reg_covar = 0.0;
  EXPECT_THROW(train(linear_map(20, 3, 0.01), o), InputError);
}

TEST(LearningModel, ConstantInputColumnAndOneDimensionalData) {
  Dataset d = flat_field(20, 11);
  Dataset with_const = d;
  with_const.input_names.push_back("tee_height");
  with_const.inputs.conservativeResize(Eigen::NoChange, 3);
  with_const.inputs.col(2).setConstant(0.25);
  Eigen::MatrixXd q = flat_field(10, 12).inputs;
  Eigen::MatrixXd q3(q.rows(), 3);
  q3 << q, Eigen::VectorXd::Constant(q.rows(), 0.25);
  for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr}) {
    // Enough GPR restarts that both find the global optimum of the marginal likelihood; the
    // constant column then changes nothing (its distances are all zero).
    TrainOptions o = options(m, 2);
    o.restarts = 20;
    const Predictions a = predict(train(d, o), q);
    const Predictions b = predict(train(with_const, o), q3);
    ASSERT_TRUE(b.mean.allFinite() && b.std.allFinite()) << method_name(m);
    EXPECT_LT((a.mean - b.mean).cwiseAbs().maxCoeff(), m == Method::kGpr ? 1e-6 : 0.02)
        << method_name(m);
  }
  Dataset one;
  one.source = "1d";
  one.input_names = {"x"};
  one.output_names = {"y"};
  one.inputs = Eigen::VectorXd::LinSpaced(12, 0.0, 3.0);
  one.outputs = one.inputs.array().sin().matrix();
  for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr}) {
    const Model model = train(one, options(m));
    const Predictions p = predict(model, Eigen::VectorXd::Constant(1, 1.5));
    EXPECT_NEAR(p.mean(0, 0), std::sin(1.5), 0.15) << method_name(m);
  }
}

TEST(LearningModel, ConstantOutputIsPredictedExactly) {
  Dataset d = flat_field(12, 21);
  d.outputs.col(1).setConstant(1.25);  // every example hit at the same speed
  const Eigen::MatrixXd q = flat_field(5, 22).inputs;
  for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr}) {
    const Predictions p = predict(train(d, options(m, 2)), q);
    ASSERT_TRUE(p.mean.allFinite() && p.std.allFinite()) << method_name(m);
    for (Eigen::Index i = 0; i < q.rows(); ++i)
      EXPECT_NEAR(p.mean(i, 1), 1.25, 1e-9) << method_name(m);
  }
}

TEST(LearningModel, AResidualModelAddsItsCorrectionToItsPriorAndRoundTrips) {
  testing::ScratchDir dir;
  const Dataset d = flat_field(20, 21);
  const Eigen::MatrixXd q = flat_field(30, 22).inputs;
  for (Method m : {Method::kGpr, Method::kGmr}) {
    auto prior = std::make_shared<Model>(train(d, options(m)));
    // The residual: a GPR on a constant correction of +0.01 for every output.
    Dataset r = d;
    r.outputs.setConstant(0.01);
    Model residual = train(r, options(Method::kGpr));
    residual.prior = prior;
    const Predictions p = predict(residual, q), base = predict(*prior, q);
    Model alone = residual;
    alone.prior.reset();
    const Predictions c = predict(alone, q);
    EXPECT_TRUE(same_bits(p.mean, Eigen::MatrixXd(base.mean + c.mean)));
    EXPECT_NEAR((p.mean - base.mean).maxCoeff(), 0.01, 1e-9);
    EXPECT_TRUE((p.std.array() >= base.std.array()).all());
    const auto path = dir / "residual.json";
    save_model(residual, path);
    const Model back = load_model(path);
    ASSERT_TRUE(back.prior);
    EXPECT_EQ(back.prior->method, m);
    EXPECT_TRUE(same_bits(predict(back, q).mean, p.mean));
    // A prior whose columns differ is refused.
    auto j = model_to_json(residual);
    j["prior"]["outputs"] = {"angle", "other"};
    EXPECT_THROW(model_from_json(j, "m.json"), InputError);
  }
}

// A residual may read more inputs than its prior (the ball's position over a prior of xi): the
// prior reads its own columns by name, wherever they stand.
TEST(LearningModel, AResidualMayAddInputsItsPriorReadsItsOwnByName) {
  testing::ScratchDir dir;
  const Dataset d = flat_field(20, 21);
  const auto prior = std::make_shared<Model>(train(d, options(Method::kGpr)));
  Dataset r = d;
  r.input_names = {"ball_x", "xi_y", "xi_x"};  // the prior's columns moved, one added
  r.inputs.resize(d.inputs.rows(), 3);
  r.inputs << Eigen::VectorXd::LinSpaced(d.inputs.rows(), 0.0, 0.4), d.inputs.col(1),
      d.inputs.col(0);
  r.outputs = 0.01 * r.inputs.col(0).replicate(1, 2);  // a correction along ball_x
  Model residual = train(r, options(Method::kGpr));
  residual.prior = prior;
  const Eigen::MatrixXd q = flat_field(10, 22).inputs;
  Eigen::MatrixXd wide(q.rows(), 3);
  wide << Eigen::VectorXd::Constant(q.rows(), 0.2), q.col(1), q.col(0);
  Model alone = residual;
  alone.prior.reset();
  const Predictions p = predict(residual, wide);
  EXPECT_TRUE(
      same_bits(p.mean, Eigen::MatrixXd(predict(*prior, q).mean + predict(alone, wide).mean)));
  const auto path = dir / "wide.json";
  save_model(residual, path);
  EXPECT_TRUE(same_bits(predict(load_model(path), wide).mean, p.mean));
  // A prior input the residual lacks is refused, naming it.
  auto j = model_to_json(residual);
  j["inputs"] = {"ball_x", "xi_y", "ball_y"};
  try {
    model_from_json(j, "m.json");
    ADD_FAILURE() << "a prior input missing from the residual was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("xi_x"), std::string::npos) << e.what();
  }
}

TEST(LearningModel, SameSeedSameModel) {
  const Dataset d = flat_field(20, 15);
  for (Method m : {Method::kGpr, Method::kGmr, Method::kJointGmr}) {
    EXPECT_EQ(model_to_json(train(d, options(m))).dump(),
              model_to_json(train(d, options(m))).dump());
  }
}

TEST(LearningModel, ScoresMatchTheirDefinitions) {
  const Dataset d = flat_field(15, 17);
  const Dataset v = flat_field(40, 18);
  const Model model = train(d, options(Method::kGmr, 2));
  const Predictions p = predict(model, v.inputs);
  const std::vector<Score> s = score(model, v);
  for (int o = 0; o < 2; ++o) {
    const Eigen::ArrayXd r = v.outputs.col(o) - p.mean.col(o);
    const Eigen::ArrayXd var = p.std.col(o).array().square();
    EXPECT_NEAR(s[o].mse, r.square().mean(), 1e-12);
    EXPECT_NEAR(s[o].nlpd, (0.5 * (2 * M_PI * var).log() + 0.5 * r.square() / var).mean(), 1e-9);
  }
}

}  // namespace
}  // namespace mg::learning
