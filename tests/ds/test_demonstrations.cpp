#include "ds/demonstrations.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"

namespace mg::ds {
namespace {

TEST(Demonstrations, GeneratorIsHumanLikeAndEndsAtTheBallAlongPsi0) {
  Rng rng(7);
  DemoGeneratorConfig cfg;
  const auto demos = generate_demonstrations(cfg, rng);
  ASSERT_EQ(demos.size(), static_cast<std::size_t>(cfg.count));
  for (const auto& d : demos) {
    ASSERT_GE(d.size(), 20u);
    const Eigen::Vector3d start = d.x.front() - cfg.ball;
    EXPECT_LE(start.x(), -cfg.behind_min + 0.005);
    EXPECT_GE(start.x(), -cfg.behind_max - 0.005);
    EXPECT_GE(start.z(), cfg.above_min - 0.005);
    EXPECT_LE(start.z(), cfg.above_max + 0.005);
    // Starts near rest, ends at the ball with the hitting speed along +x.
    EXPECT_LT(d.xdot.front().norm(), 0.1);
    EXPECT_LT((d.x.back() - cfg.ball).norm(), 0.003);
    const double v_end = d.xdot.back().norm();
    EXPECT_NEAR(v_end, cfg.hitting_speed, 0.15);
    EXPECT_GT(d.xdot.back().normalized().x(), std::cos(3.0 * M_PI / 180.0));
    // Bell-shaped speed: the peak is near the end and the speed at the ball stays high.
    double peak = 0.0;
    for (const auto& v : d.xdot) peak = std::max(peak, v.norm());
    EXPECT_GT(v_end, 0.9 * peak);
    // Velocities are consistent with the positions (finite differences, loose: noise).
    for (std::size_t i = 1; i + 1 < d.size(); i += 5) {
      const Eigen::Vector3d fd = (d.x[i + 1] - d.x[i - 1]) / (d.t[i + 1] - d.t[i - 1]);
      EXPECT_LT((fd - d.xdot[i]).norm(), 0.1) << "sample " << i;
    }
  }
}

TEST(Demonstrations, SameSeedSameBitsDifferentSeedDifferentData) {
  DemoGeneratorConfig cfg;
  Rng a(3), b(3), c(4);
  EXPECT_EQ(format_demonstrations(generate_demonstrations(cfg, a)),
            format_demonstrations(generate_demonstrations(cfg, b)));
  Rng a2(3);
  EXPECT_NE(format_demonstrations(generate_demonstrations(cfg, a2)),
            format_demonstrations(generate_demonstrations(cfg, c)));
}

TEST(Demonstrations, CsvRoundTripIsExact) {
  Rng rng(1);
  DemoGeneratorConfig cfg;
  cfg.count = 3;
  const auto demos = generate_demonstrations(cfg, rng);
  const auto back = demonstrations_from_table(parse_csv(format_demonstrations(demos), "mem"));
  ASSERT_EQ(back.size(), demos.size());
  for (std::size_t k = 0; k < demos.size(); ++k) {
    ASSERT_EQ(back[k].size(), demos[k].size());
    for (std::size_t i = 0; i < demos[k].size(); ++i) {
      EXPECT_EQ(back[k].x[i], demos[k].x[i]);
      EXPECT_EQ(back[k].xdot[i], demos[k].xdot[i]);
    }
  }
}

TEST(Demonstrations, ShippedDefaultSetIsValid) {
  const auto demos = read_demonstrations(data_dir() / "demos" / "default.csv");
  EXPECT_GE(demos.size(), 5u);
  const auto s = summarize_demonstrations(demos);
  EXPECT_LT((s.x_star - Eigen::Vector3d(0, 0, kBallRadius)).norm(), 0.002);
  EXPECT_GT(s.psi0.x(), 0.999);
  EXPECT_GT(s.hitting_speed, 1.0);
  EXPECT_LT(s.hitting_speed, 2.0);
}

TEST(Demonstrations, BadInputIsAClearError) {
  const std::string header = "demo,t,x,y,z,vx,vy,vz\n";
  EXPECT_THROW(demonstrations_from_table(parse_csv(header, "empty")), InputError);
  EXPECT_THROW(demonstrations_from_table(parse_csv(header + "0,0,0,0,0,1,0,0\n", "one")),
               InputError);
  EXPECT_THROW(parse_csv(header + "0,0,nan,0,0,1,0,0\n0,1,0,0,0,1,0,0\n", "nan"), InputError);
  EXPECT_THROW(demonstrations_from_table(parse_csv("demo,t,x,y,z\n0,0,0,0,0\n0,1,0,0,0\n", "cols")),
               InputError);
  EXPECT_THROW(
      demonstrations_from_table(parse_csv(header + "0,1,0,0,0,1,0,0\n0,0.5,0,0,0,1,0,0\n", "time")),
      InputError);
  EXPECT_THROW(
      demonstrations_from_table(parse_csv(header + "0.5,0,0,0,0,1,0,0\n0.5,1,0,0,0,1,0,0\n", "id")),
      InputError);
  EXPECT_THROW(summarize_demonstrations({}), InputError);

  // Demonstrations that do not share an end point.
  Rng rng(5);
  DemoGeneratorConfig cfg;
  cfg.count = 2;
  auto demos = generate_demonstrations(cfg, rng);
  EXPECT_NO_THROW(summarize_demonstrations(demos));
  for (auto& p : demos[1].x) p += Eigen::Vector3d(0.0, 0.1, 0.0);
  try {
    summarize_demonstrations(demos);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("common end point"), std::string::npos) << e.what();
  }
  // Ending at rest is not a hit.
  demos = generate_demonstrations(cfg, rng);
  demos[0].xdot.back().setZero();
  EXPECT_THROW(summarize_demonstrations(demos), InputError);
}

// Found by fuzzing: one velocity of 1e200 crashed `ds fit --gaussians 1`.
TEST(Demonstrations, HugeValuesAreAClearErrorNamingTheFile) {
  const CsvTable t = parse_csv(
      "demo,t,x,y,z,vx,vy,vz\n0,0,0,0,0,1e200,0,0\n0,0.1,0.1,0,0,1,0,0\n0,0.2,0.2,0,0,0,0,0\n",
      "d.csv");
  try {
    demonstrations_from_table(t, 1);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("d.csv: row 1: column 'vx'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mg::ds
