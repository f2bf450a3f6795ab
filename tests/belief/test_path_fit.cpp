// Identification of the green from ball paths: the point model against itself, MuJoCo's paths
// of known plants, the identity's uncertainty, and the cost.
#include "belief/path_fit.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <string>

#include <gtest/gtest.h>

#include "belief_test_util.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "field/field.hpp"
#include "plant/plant.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"

namespace mg::belief {
namespace {

using test::gaussian;

/// Putts across the lane from the tee: angles and launch speeds [m/s].
struct Shot {
  double angle, speed;
};
const std::vector<Shot> kShots{{0.15, 2.4},  {-0.15, 1.9}, {0.08, 1.9},
                               {-0.08, 2.4}, {0.2, 2.1},   {-0.2, 2.1}};

/// MuJoCo's paths of `shots` on the true field of `plant` over `field`, perceived with a
/// Gaussian error of `noise` [m] per axis and sample.
std::vector<ObservedPath> mujoco_paths(const field::Field& field, const plant::Plant& plant,
                                       const std::vector<Shot>& shots, double noise,
                                       std::uint64_t seed = 1) {
  const sim::World world(plant::true_field(field, plant));
  auto d = world.make_data();
  std::vector<ObservedPath> paths;
  Rng rng(seed);
  for (const Shot& s : shots) {
    sim::PuttRequest q;
    q.angle = s.angle;
    q.speed = s.speed;
    q.record_interval = 0.01;
    const sim::PuttOutcome out = sim::simulate_putt(world, d.get(), field.hole.position, q);
    ObservedPath p;
    for (const sim::BallSample& b : out.trajectory)
      p.samples.push_back({b.t, b.x + noise * gaussian(rng), b.y + noise * gaussian(rng)});
    paths.push_back(std::move(p));
  }
  return paths;
}

plant::Plant green_plant(double rho_scale, double sx, double sy) {
  plant::Plant p;
  p.field.rolling_resistance_scale = rho_scale;
  p.field.extra_slope = {sx, sy};
  return p;
}

// The point model's own paths: the fit finds rho and the tilt it made them with.
TEST(FitGreen, RecoversThePointModelsOwnPaths) {
  for (const char* name : {"flat", "regular-hill", "arctan"}) {
    const field::Field field = field::load_field(name);
    const GreenParams truth{0.15, {0.003, -0.002}};
    std::vector<ObservedPath> paths;
    const std::vector<RollState> starts{{0.3, 0.05, 2.0, 0.3},
                                        {0.3, -0.05, 1.6, -0.3},
                                        {0.4, 0.2, 1.8, -0.25},
                                        {0.4, -0.2, 2.2, 0.2}};
    for (const RollState& s : starts) {
      std::vector<double> times;
      for (int i = 0; i <= 300; ++i) times.push_back(0.01 * i);
      const auto xy = predict_roll(field, truth, s, times);
      ObservedPath p;
      for (std::size_t i = 0; i < times.size(); ++i)
        p.samples.push_back({times[i], xy[i][0], xy[i][1]});
      paths.push_back(std::move(p));
    }
    // Exact samples: a tiny vision error, so that the spin's prior does not pull.
    const GreenEstimate e = fit_green(field, paths, GreenPrior{}, 1e-7);
    EXPECT_GE(e.paths_used, 3) << name;  // a stall or a fast hill's foot may cut one
    EXPECT_NEAR(e.rolling_resistance, truth.rolling_resistance, 1e-3 * truth.rolling_resistance)
        << name;
    EXPECT_NEAR(e.extra_slope[0], truth.extra_slope[0], 1e-6) << name;
    EXPECT_NEAR(e.extra_slope[1], truth.extra_slope[1], 1e-6) << name;
    EXPECT_LT(e.rms_residual, 1e-6) << name;
  }
}

// MuJoCo's ball on a plant's lane: rho within 1 %, each slope within 1 mrad.
TEST(FitGreen, RecoversAPlantFromMujocoPaths) {
  for (const char* name : {"flat", "multiple-hills", "regular-hill", "arctan"}) {
    const field::Field field = field::load_field(name);
    const plant::Plant plant = green_plant(1.15, 0.003, -0.002);
    const auto paths = mujoco_paths(field, plant, kShots, 0.0);
    const auto t0 = std::clock();
    const GreenEstimate e = fit_green(field, paths, GreenPrior{}, 0.0);
    const double cpu = static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
    const double rho = plant::true_rolling_resistance(field, plant);
    std::printf(
        "%s: rho %.5f (true %.5f, %.3f %%), slope %.6f %.6f, std %.2g %.2g %.2g, rms %.2g m, "
        "%d paths %d samples, %d it, %.3f s\n",
        name, e.rolling_resistance, rho, 100 * (e.rolling_resistance / rho - 1), e.extra_slope[0],
        e.extra_slope[1], e.std[0], e.std[1], e.std[2], e.rms_residual, e.paths_used,
        e.samples_used, e.iterations, cpu);
    EXPECT_NEAR(e.rolling_resistance, rho, 0.01 * rho) << name;
    EXPECT_NEAR(e.extra_slope[0], 0.003, 1e-3) << name;
    EXPECT_NEAR(e.extra_slope[1], -0.002, 1e-3) << name;
  }
}

// The identity: the survey's own lane, perceived with 0.5 mm of vision error; the estimate lies
// within 3 standard deviations of the survey.
TEST(FitGreen, TheIdentityLiesWithinItsUncertaintyOfTheSurvey) {
  for (const char* name : {"flat", "arctan"}) {
    const field::Field field = field::load_field(name);
    const auto paths = mujoco_paths(field, plant::Plant{}, kShots, 5e-4, 7);
    const GreenEstimate e = fit_green(field, paths, GreenPrior{}, 5e-4);
    EXPECT_LT(std::abs(e.rolling_resistance - field.rolling_resistance), 3.0 * e.std[0]) << name;
    EXPECT_LT(std::abs(e.extra_slope[0]), 3.0 * e.std[1]) << name;
    EXPECT_LT(std::abs(e.extra_slope[1]), 3.0 * e.std[2]) << name;
    EXPECT_NEAR(e.rms_residual, 5e-4, 0.5e-4) << name;  // the vision's error, no model error
    EXPECT_LT(e.std[0], 0.01 * field.rolling_resistance) << name;
    EXPECT_LT(e.std[1], 1e-3) << name;
  }
}

// A belief update must be cheap: 10 paths on the costliest lane in under a second of CPU (the
// budget; typically 50-150 ms), the same bits twice.
TEST(FitGreen, TenPathsTakeUnderASecondAndRepeatBitForBit) {
  const field::Field field = field::load_field("multiple-hills");
  std::vector<Shot> shots = kShots;
  shots.push_back({0.12, 1.7});
  shots.push_back({-0.12, 2.2});
  shots.push_back({0.25, 1.6});
  shots.push_back({-0.25, 1.8});
  const auto paths = mujoco_paths(field, green_plant(0.9, -0.002, 0.004), shots, 5e-4, 3);
  const auto t0 = std::clock();
  const GreenEstimate a = fit_green(field, paths, GreenPrior{}, 0.0);
  const double cpu = static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
  std::printf("multiple-hills, 10 paths: %.3f s CPU, %d steps\n", cpu, a.iterations);
  EXPECT_LT(cpu, 1.0);
  const GreenEstimate b = fit_green(field, paths, GreenPrior{}, 0.0);
  EXPECT_EQ(a.rolling_resistance, b.rolling_resistance);
  EXPECT_EQ(a.extra_slope, b.extra_slope);
  EXPECT_EQ(a.std, b.std);
}

TEST(FitGreen, BadInputsAreNamed) {
  const field::Field field = field::load_field("flat");
  ObservedPath p;
  p.samples = {{0.0, 0.0, 0.0}, {0.01, 0.02, 0.0}, {0.01, 0.04, 0.0}};
  EXPECT_THROW(fit_green(field, {p}, GreenPrior{}, 0.0), InputError);  // times not ascending
  p.samples[2] = {0.02, NAN, 0.0};
  EXPECT_THROW(fit_green(field, {p}, GreenPrior{}, 0.0), InputError);
  EXPECT_THROW(fit_green(field, {}, GreenPrior{}, -1.0), InputError);
  GreenPrior bad;
  bad.std[1] = 0.0;
  EXPECT_THROW(fit_green(field, {}, bad, 0.0), InputError);
  // Paths too short to roll: nothing to identify from.
  p.samples[2] = {0.02, 0.04, 0.0};
  try {
    fit_green(field, {p, p}, GreenPrior{}, 0.0);
    ADD_FAILURE() << "no error";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("none of the 2 paths"), std::string::npos) << e.what();
  }
}

// A path is cut where it meets a border or the hole, and its slide is dropped.
TEST(RollingSpan, DropsTheSlideAndStopsAtTheBorder) {
  const field::Field field = field::load_field("flat");
  const auto paths = mujoco_paths(field, plant::Plant{}, {{0.5, 2.4}}, 0.0);
  const auto& s = paths[0].samples;
  const auto span = rolling_span(field, paths[0]);
  ASSERT_LT(span[0], span[1]);
  // The slide of a ball launched at 2.4 m/s without spin: 2 v0 / (7 mu g) = 0.233 s.
  EXPECT_GT(s[span[0]][0], 0.233);
  const double y = s[span[1] - 1][2];
  EXPECT_LT(y, field.bounds[3] - field.ball.radius - 0.02);  // before the wall at y = 0.6
  double furthest = y;                                       // the ball went on to the wall
  for (std::size_t i = span[1]; i < s.size(); ++i) furthest = std::max(furthest, s[i][2]);
  EXPECT_GT(furthest, field.bounds[3] - field.ball.radius - 0.005);
}

// A putt over the bumps of multiple hills at a learning putt's speed: its first rolling run ends
// at a crest, later runs read the lane beyond, and every run makes the green better known.
TEST(RollingSpans, ReadAPuttOverCrestsOnBothSidesOfEach) {
  const field::Field field = field::load_field("multiple-hills");
  const plant::Plant plant = green_plant(0.85, 0.003, -0.003);
  const std::vector<Shot> shots{{0.06, 2.9}, {0.09, 2.9}, {0.03, 2.8}, {0.1, 2.85}};
  const auto paths = mujoco_paths(field, plant, shots, 0.0005);
  std::size_t runs = 0;
  for (const auto& p : paths) {
    const auto spans = rolling_spans(field, p);
    const auto first = rolling_span(field, p);
    if (first[1] > first[0]) {
      ASSERT_FALSE(spans.empty());
      EXPECT_EQ(spans.front(), first);
    }
    for (std::size_t k = 0; k < spans.size(); ++k) {
      EXPECT_GE(spans[k][1], spans[k][0] + 8);
      if (k > 0) {
        EXPECT_GT(spans[k][0], spans[k - 1][1]);  // apart, in order
      }
    }
    runs += spans.size();
  }
  EXPECT_GT(runs, paths.size()) << "no putt crossed a crest at speed";
  const GreenPrior prior{
      field.rolling_resistance, {0.0, 0.0}, {0.25 * field.rolling_resistance, 0.01, 0.01}};
  const GreenEstimate first_only = fit_green(field, paths, prior, 0.0);
  const GreenEstimate every = fit_green(field, paths, prior, 0.0, true);
  EXPECT_GT(every.samples_used, first_only.samples_used);
  EXPECT_EQ(every.paths_used, static_cast<int>(paths.size()));
  EXPECT_LT(every.std[0], first_only.std[0]);
  const double rho = plant::true_rolling_resistance(field, plant);
  EXPECT_NEAR(every.rolling_resistance, rho, 3.0 * every.std[0] + 0.01 * rho);
}

}  // namespace
}  // namespace mg::belief
