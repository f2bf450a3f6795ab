// Fitting SEDS (src/ds/seds_fit.cpp): the initial guess, the constrained optimisation.
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "ds/seds.hpp"
#include "seds_test_util.hpp"

namespace mg::ds {
namespace {

using testing::demo_data;

TEST(Seds, InitialGuessIsFeasible) {
  const SedsData data = demo_data(4, 9);
  SedsOptions opt;
  opt.gaussians = 3;
  for (const auto& c : seds_initial_guess(data, opt))
    EXPECT_LT(stability_eigenvalue(c.a), -opt.optimizer_margin);
}

class SedsFit : public ::testing::TestWithParam<SedsObjective> {};

TEST_P(SedsFit, ConstraintsHoldAndObjectiveImproves) {
  const SedsData data = demo_data(5, 21);
  SedsOptions opt;
  opt.gaussians = 3;
  opt.objective = GetParam();
  opt.max_evaluations = 300;
  const SedsResult r = fit_seds(data, opt);
  EXPECT_LE(r.final_objective, r.initial_objective);
  EXPECT_LE(r.max_eigenvalue, -opt.margin);
  for (const auto& c : r.components) EXPECT_LE(stability_eigenvalue(c.a), -opt.margin);
  // Lyapunov: f(y) . y < 0 everywhere away from the origin (checked on a grid, also far away).
  for (double x = -3.0; x <= 3.0; x += 0.5)
    for (double y = -3.0; y <= 3.0; y += 0.75)
      for (double z = -1.0; z <= 2.0; z += 0.75) {
        const Eigen::Vector3d p(x * 0.3, y * 0.3, z * 0.3);
        if (p.norm() < 1e-9) continue;
        const Eigen::Vector3d f = seds_velocity(r.components, p);
        ASSERT_TRUE(f.allFinite());
        EXPECT_LT(f.dot(p), 0.0);
      }
  // Same seed, same bits.
  const SedsResult again = fit_seds(data, opt);
  EXPECT_EQ(pack_seds(r.components, opt.objective, opt.covariance_floor),
            pack_seds(again.components, opt.objective, opt.covariance_floor));
}

INSTANTIATE_TEST_SUITE_P(Objectives, SedsFit,
                         ::testing::Values(SedsObjective::kLikelihood, SedsObjective::kMse));

TEST(Seds, NoisyAndFewDemonstrationsStillGiveAStableModel) {
  for (const auto& [count, noise] :
       std::vector<std::pair<int, double>>{{1, 1.0}, {2, 10.0}, {6, 20.0}}) {
    const SedsData data = demo_data(count, 100 + static_cast<std::uint64_t>(count), noise);
    SedsOptions opt;
    opt.gaussians = 2;
    opt.max_evaluations = 200;
    const SedsResult r = fit_seds(data, opt);
    EXPECT_LE(r.max_eigenvalue, -opt.margin) << count << " demos, noise x" << noise;
  }
}

}  // namespace
}  // namespace mg::ds
