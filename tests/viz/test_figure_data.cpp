// The numbers behind the model figures, checked against the model's own functions and closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "ds/hitting_ds.hpp"
#include "system/system.hpp"
#include "viz/figure_data.hpp"

namespace mg::viz {
namespace {

struct Shipped {
  ds::HittingModel model = ds::read_hitting_model(system::load_config("").hitting_model);
  std::vector<ds::Demonstration> demos =
      ds::read_demonstrations(system::resolve_data_path("data/demos/default.csv"));
};

TEST(FigureData, StrengthFactorMeetsTheDefaultSpeedAtTheBall) {
  const Shipped s;
  const CsvTable t = parse_csv(strength_csv(s.model, s.demos), "strength");
  const auto r = t.column("distance"), v = t.column("strength");
  ASSERT_GT(r.size(), 100u);
  double near_ball = -1.0, best = 1e9;
  for (std::size_t i = 0; i < r.size(); ++i) {
    EXPECT_GE(v[i], s.model.settings().min_strength_fraction * s.model.default_speed() - 1e-9);
    EXPECT_LE(v[i], s.model.settings().max_strength_fraction * s.model.default_speed() + 1e-9);
    if (r[i] < best) best = r[i], near_ball = v[i];
  }
  ASSERT_LT(best, 0.01);
  EXPECT_NEAR(near_ball, s.model.default_speed(), 0.02 * s.model.default_speed());
}

TEST(FigureData, ModulatorsFollowEquations26) {
  const Shipped s;
  const CsvTable t = parse_csv(modulators_csv(s.model, s.demos, {0.5, 1.5}), "mods");
  const auto r = t.column("r"), c = t.column("s_constant_1.5"), sine = t.column("s_sine_1.5");
  const double s_d = 1.5 / s.model.default_speed();
  const double d0 = r.back() / 1.2;
  EXPECT_NEAR(c.front(), s_d, 1e-12);
  EXPECT_NEAR(c.back(), s_d, 1e-12);
  EXPECT_NEAR(sine.front(), s_d, 1e-12);  // at the ball: the commanded speed
  EXPECT_NEAR(sine.back(), 1.0, 1e-12);   // beyond d0: the demonstrated speed
  const std::size_t mid = r.size() / 2;   // r = 0.6 d0
  const double expected = s_d + (1 - s_d) * std::pow(std::sin(M_PI * r[mid] / (2 * d0)), 2);
  EXPECT_NEAR(sine[mid], expected, 1e-12);
  EXPECT_THROW(modulators_csv(s.model, s.demos, {}), InputError);
  EXPECT_THROW(modulators_csv(s.model, s.demos, {-1.0}), InputError);
}

TEST(FigureData, DsFieldIsTheDsVelocityInThePlane) {
  const Shipped s;
  const CsvTable t = parse_csv(ds_field_csv(s.model, s.demos, DsPlane::kXz, 5), "field");
  ASSERT_EQ(t.num_rows(), 25u);
  ds::HittingDsData data(s.model);
  ds::HittingCommand c;
  c.speed = s.model.default_speed();
  c.start = s.model.x_star() - 0.3 * s.model.psi0();
  data.set_command(s.model, c);
  const auto a = t.column("a"), b = t.column("b"), u = t.column("u"), w = t.column("v");
  for (std::size_t i = 0; i < a.size(); i += 6) {
    const Eigen::Vector3d x(a[i], s.model.x_star().y(), b[i]);
    const Eigen::Vector3d v = ds::hitting_ds_velocity(s.model, data, x);
    EXPECT_DOUBLE_EQ(u[i], v.x());
    EXPECT_DOUBLE_EQ(w[i], v.z());
  }
  EXPECT_THROW(parse_ds_plane("yz"), InputError);
  const CsvTable g = parse_csv(gmm_csv(s.model), "gmm");
  EXPECT_EQ(static_cast<int>(g.num_rows()), s.model.seds_gmm().num_components());
}

TEST(FigureData, PredictionsCoverTheDataRange) {
  learning::Dataset d;
  d.input_names = {"xi_y"};
  d.output_names = {"angle"};
  d.inputs = Eigen::MatrixXd(4, 1);
  d.inputs << -0.2, 0.0, 0.2, 0.4;
  d.outputs = Eigen::MatrixXd(4, 1);
  d.outputs << -0.1, 0.0, 0.1, 0.2;
  learning::TrainOptions o;
  o.restarts = 2;
  const learning::Model m = learning::train(d, o);
  const CsvTable t = parse_csv(predictions_csv(m, d), "pred");
  const auto q = t.column("xi_y"), mean = t.column("angle_mean"), sd = t.column("angle_std");
  ASSERT_EQ(q.size(), 101u);
  EXPECT_LT(q.front(), -0.2);
  EXPECT_GT(q.back(), 0.4);
  for (std::size_t i = 0; i < q.size(); ++i) EXPECT_GT(sd[i], 0.0);
  // Near a training point the GP mean is near its target (a straight line here).
  EXPECT_NEAR(mean[50], 0.5 * q[50], 0.02);
}

}  // namespace
}  // namespace mg::viz
