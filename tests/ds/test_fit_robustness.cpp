// A hitting-model fit on valid demonstrations never fails, whatever K, on
// smooth (nearly noise-free) and noisy demonstrations; it says what it did on its own; and the
// result is stable (deterministic, stable DS, every demonstration reproduced to the ball).
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "../slow_test.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "ds/demonstrations.hpp"
#include "ds/hitting_ds.hpp"
#include "ds/hitting_model.hpp"

namespace mg::ds {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kDeg = 180.0 / std::numbers::pi;

/// The reproducer: six cubic (Hermite) approaches from rest to the ball, arriving along +x
/// at 1.5 m/s after 0.5 s, 51 samples each, i.i.d. Gaussian noise of `noise` m on positions and
/// 10 x `noise` m/s on velocities.
std::vector<Demonstration> cubic_demos(double noise, std::uint64_t seed) {
  Rng rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Vec3 ball(0.0, 0.0, kBallRadius);
  const double duration = 0.5, speed = 1.5;
  std::vector<Demonstration> demos;
  for (int d = 0; d < 6; ++d) {
    Demonstration demo;
    demo.id = d;
    const Vec3 p0 = ball + Vec3(-0.3 - 0.03 * d, 0.02 * (d - 2.5), 0.05 + 0.02 * d);
    const Vec3 m1(speed * duration, 0.0, 0.0);
    for (int i = 0; i <= 50; ++i) {
      const double s = i / 50.0;
      const double h00 = 2 * s * s * s - 3 * s * s + 1, h01 = -2 * s * s * s + 3 * s * s,
                   h11 = s * s * s - s * s;
      const double d00 = 6 * s * s - 6 * s, d01 = -6 * s * s + 6 * s, d11 = 3 * s * s - 2 * s;
      Vec3 x = h00 * p0 + h01 * ball + h11 * m1;
      Vec3 v = (d00 * p0 + d01 * ball + d11 * m1) / duration;
      for (int a = 0; a < 3; ++a) {
        x[a] += noise * gauss(rng);
        v[a] += 10.0 * noise * gauss(rng);
      }
      demo.t.push_back(s * duration);
      demo.x.push_back(x);
      demo.xdot.push_back(v);
    }
    demos.push_back(std::move(demo));
  }
  return demos;
}

struct Case {
  std::string name;
  std::vector<Demonstration> demos;
};

std::vector<Case> cases() {
  DemoGeneratorConfig generated;
  generated.count = 6;
  Rng rng(7);
  return {{"cubic smooth 1e-5", cubic_demos(1e-5, 1)},
          {"cubic noisy 1e-3", cubic_demos(1e-3, 2)},
          {"generator default noise", generate_demonstrations(generated, rng)}};
}

class FitEveryK : public ::testing::TestWithParam<int> {};

TEST_P(FitEveryK, SucceedsAndIsStableOnSmoothAndNoisyDemonstrations) {
  const int k = GetParam();
  if (k >= 5) MG_SLOW_TEST();
  for (const Case& c : cases()) {
    HittingFitOptions opt;
    opt.seds.gaussians = k;
    opt.seds.seed = 3;
    opt.seds.max_evaluations = 600;
    HittingFitReport rep;
    std::optional<HittingModel> model;
    ASSERT_NO_THROW(model.emplace(fit_hitting_model(c.demos, opt, &rep)))
        << c.name << ", K = " << k;
    const int used = static_cast<int>(rep.seds.components.size());
    EXPECT_GE(used, 1);
    EXPECT_LE(used, k);
    // Fewer components than asked for is always explained.
    if (used < k) {
      EXPECT_FALSE(rep.notes.empty()) << c.name << ", K = " << k;
    }
    EXPECT_EQ(model->provenance.contains("fit_notes"), !rep.notes.empty());
    EXPECT_LE(model->max_eigenvalue(), -1e-4) << c.name << ", K = " << k;
    const ReproductionError err = reproduction_error(*model, c.demos);
    EXPECT_EQ(err.all_reached, 6) << c.name << ", K = " << k;
    // Rollouts from the demonstration starts stay near the demonstrated paths (a linear DS
    // (K = 1) cannot follow the curved cubic paths closely: measured mean 0.005-0.055 m).
    EXPECT_LT(err.mean_path_distance, 0.08) << c.name << ", K = " << k;
    EXPECT_LT(err.direction_rmse * kDeg, 70.0) << c.name << ", K = " << k;
    // Deterministic: the same fit again gives the same model, bit for bit.
    const HittingModel again = fit_hitting_model(c.demos, opt);
    EXPECT_EQ(hitting_model_to_json(again).dump(), hitting_model_to_json(*model).dump())
        << c.name << ", K = " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(K1to6, FitEveryK, ::testing::Range(1, 7));

TEST(FitBounds, TooManyGaussiansIsAnInputErrorNamingTheBound) {
  HittingFitOptions opt;
  opt.seds.gaussians = kMaxSedsGaussians + 1;
  try {
    fit_hitting_model(cubic_demos(1e-5, 1), opt);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxSedsGaussians)), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mg::ds
