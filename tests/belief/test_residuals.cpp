// What the fitted green leaves out: white vision error reads as white, an unsurveyed bump as
// structure, and a belief that holds the bump reads white again.
#include "belief/residuals.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "belief_test_util.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "field/field.hpp"
#include "plant/plant.hpp"

namespace mg::belief {
namespace {

using test::gaussian;

/// The point model's paths on `truth` from four starts, 2.5 s at 100 Hz, with a Gaussian vision
/// error of `noise` [m] per axis and sample.
std::vector<ObservedPath> paths_on(const field::Field& truth, double noise) {
  const GreenParams green{truth.rolling_resistance, {0.0, 0.0}};
  const std::vector<RollState> starts{{0.3, 0.05, 2.0, 0.25},
                                      {0.3, -0.05, 1.7, -0.2},
                                      {0.4, 0.2, 1.9, -0.3},
                                      {0.4, -0.2, 2.1, 0.3}};
  Rng rng(7);
  std::vector<ObservedPath> paths;
  for (const RollState& s : starts) {
    std::vector<double> times;
    for (int i = 0; i <= 250; ++i) times.push_back(0.01 * i);
    const auto xy = predict_roll(truth, green, s, times);
    ObservedPath p;
    for (std::size_t i = 0; i < times.size(); ++i)
      p.samples.push_back(
          {times[i], xy[i][0] + noise * gaussian(rng), xy[i][1] + noise * gaussian(rng)});
    paths.push_back(std::move(p));
  }
  return paths;
}

plant::Plant bumpy() {
  plant::Plant p;
  field::BumpTerm bump;
  bump.center = {1.3, 0.0};
  bump.height = 0.003;
  bump.sigma = {0.25, 0.25};
  p.field.bumps.push_back(bump);
  return p;
}

TEST(Residuals, VisionErrorReadsWhiteAndABumpTheSurveyMissedReadsStructured) {
  const field::Field flat = field::load_field("flat");
  const double noise = 0.0005;
  const GreenEstimate white = fit_green(flat, paths_on(flat, noise), GreenPrior{}, 0.0, true);
  const ResidualSummary w = summarize_residuals(white);
  EXPECT_GT(w.samples, 300);
  EXPECT_FALSE(w.structured) << w.lag1;
  EXPECT_LT(std::abs(w.lag1), 0.15);
  EXPECT_NEAR(w.rms_along, noise, 0.2 * noise);
  EXPECT_NEAR(w.rms_across, noise, 0.2 * noise);

  const field::Field truth = plant::true_field(flat, bumpy());
  const auto seen = paths_on(truth, noise);
  const ResidualSummary b = summarize_residuals(fit_green(flat, seen, GreenPrior{}, 0.0, true));
  EXPECT_TRUE(b.structured) << b.lag1 << " " << b.rms_along << " " << b.rms_across;
  EXPECT_GT(b.lag1, 0.5);
  // White error of `noise` per axis is sqrt(2) noise in all.
  EXPECT_GT(std::hypot(b.rms_along, b.rms_across), 1.25 * std::sqrt(2.0) * noise);
  ASSERT_FALSE(b.bins.empty());
  int over_bump = 0;
  for (const ResidualBin& bin : b.bins) over_bump += bin.x_from < 1.3 && bin.x_to > 1.3;
  EXPECT_EQ(over_bump, 1);

  // The same paths fitted on a lane that has the bump: white again.
  const ResidualSummary c = summarize_residuals(fit_green(truth, seen, GreenPrior{}, 0.0, true));
  EXPECT_FALSE(c.structured) << c.lag1;
  EXPECT_LT(std::hypot(c.rms_along, c.rms_across), 1.1 * std::sqrt(2.0) * noise);
}

TEST(Residuals, ABinWidthThatIsNotPositiveIsRefused) {
  const GreenEstimate none;
  EXPECT_THROW(summarize_residuals(none, 0.0), InputError);
  EXPECT_THROW(summarize_residuals(none, std::nan("")), InputError);
  EXPECT_EQ(summarize_residuals(none).samples, 0);
}

}  // namespace
}  // namespace mg::belief
