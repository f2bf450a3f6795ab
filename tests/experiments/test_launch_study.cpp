// The launch-error study (thesis 6.1) and the execution noise of full_system_putt.
#include "experiments/launch_study.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "field/field.hpp"

namespace mg::experiments {
using control::full_system_putt;
using control::FullPuttOptions;
using control::FullPuttResult;
namespace {

struct StudyRig {
  system::System system{system::load_config("", "flat")};
  system::SystemData data{system};
  const sim::World& world = system.arm_world();
  const control::ModuleModel& model = system.module();
};

StudyRig& rig() {
  static StudyRig r;
  return r;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_hits(const LaunchStudyResult& a, const LaunchStudyResult& b) {
  ASSERT_EQ(a.hits.size(), b.hits.size());
  for (std::size_t i = 0; i < a.hits.size(); ++i) {
    EXPECT_TRUE(same_bits(a.hits[i].launch_angle, b.hits[i].launch_angle)) << i;
    EXPECT_TRUE(same_bits(a.hits[i].launch_speed, b.hits[i].launch_speed)) << i;
    EXPECT_TRUE(same_bits(a.hits[i].club_speed, b.hits[i].club_speed)) << i;
    EXPECT_TRUE(same_bits(a.hits[i].ball_start[1], b.hits[i].ball_start[1])) << i;
  }
}

void print(const LaunchStudyResult& r) { std::printf("%s", launch_study_markdown(r).c_str()); }

LaunchStudyOptions small(double torque_noise, double placement_noise, std::uint64_t seed = 1) {
  LaunchStudyOptions o;
  o.angles_deg = {0.0};
  o.hits = 3;
  o.torque_noise = torque_noise;
  o.placement_noise = placement_noise;
  o.seed = seed;
  return o;
}

// Zero noise: the putt is exactly the noise-free full_system_putt, every hit the same bits.
TEST(LaunchStudy, ZeroNoiseGivesZeroStdAndTheNoiseFreePutt) {
  const auto r = run_launch_study(rig().system, small(0.0, 0.0));
  print(r);
  ASSERT_EQ(r.summary.size(), 1u);
  EXPECT_EQ(r.summary[0].n, 3);
  EXPECT_EQ(r.summary[0].std_error_deg, 0.0);
  EXPECT_EQ(r.summary[0].std_club_speed_error, 0.0);
  EXPECT_EQ(r.summary[0].std_launch_club_ratio, 0.0);
  const FullPuttResult plain =
      full_system_putt(rig().world, rig().model, rig().data.arm.get(), {2.0, 0.0}, 0.0, 1.0);
  for (const LaunchHit& h : r.hits) {
    EXPECT_TRUE(same_bits(h.launch_angle, plain.launch.angle));
    EXPECT_TRUE(same_bits(h.club_speed, plain.club.speed));
    EXPECT_EQ(h.ball_start[0], 0.0);
    EXPECT_EQ(h.ball_start[1], 0.0);
  }
  // A seed without noise changes nothing.
  FullPuttOptions seeded;
  seeded.seed = 12345;
  const FullPuttResult s = full_system_putt(rig().world, rig().model, rig().data.arm.get(),
                                            {2.0, 0.0}, 0.0, 1.0, seeded);
  EXPECT_TRUE(same_bits(s.launch.angle, plain.launch.angle));
  EXPECT_TRUE(same_bits(s.outcome.rest_position[0], plain.outcome.rest_position[0]));
  EXPECT_EQ(s.outcome.steps, plain.outcome.steps);
}

// With noise: spread > 0; same seed same bits; another seed other bits; 0 deg nearly unbiased.
TEST(LaunchStudy, NoiseIsSeededAndSpreadsTheLaunch) {
  const auto a = run_launch_study(rig().system, small(0.01, 0.001, 7), 1);
  const auto b = run_launch_study(rig().system, small(0.01, 0.001, 7), 2);  // 2 threads, same bits
  const auto c = run_launch_study(rig().system, small(0.01, 0.001, 8));
  print(a);
  print(c);
  ASSERT_EQ(a.summary[0].n, 3);
  EXPECT_GT(a.summary[0].std_error_deg, 0.0);
  EXPECT_GT(a.summary[0].std_club_speed_error, 0.0);
  expect_same_hits(a, b);
  EXPECT_FALSE(same_bits(a.hits[0].launch_angle, c.hits[0].launch_angle));
  EXPECT_LT(std::abs(a.summary[0].mean_error_deg), 0.5);
  EXPECT_LT(std::abs(c.summary[0].mean_error_deg), 0.5);
  for (const LaunchHit& h : a.hits) {
    EXPECT_TRUE(h.hit);
    EXPECT_LT(std::abs(h.club_speed_error), 0.1);
    EXPECT_GT(h.launch_club_ratio, 1.3);  // a putter-like impact (restitution 0.8)
    EXPECT_LT(h.launch_club_ratio, 1.9);
    EXPECT_LT(std::hypot(h.ball_start[0], h.ball_start[1]), 0.01);
    EXPECT_NE(h.ball_start[1], 0.0);
  }
}

// Each noise source on its own spreads the launch; the seed of a hit does not depend on the
// other angles in the list.
TEST(LaunchStudy, EachNoiseSourceAloneAndSeedsIndependentOfOrder) {
  const auto torque = run_launch_study(rig().system, small(0.01, 0.0));
  const auto place = run_launch_study(rig().system, small(0.0, 0.001));
  EXPECT_GT(torque.summary[0].std_error_deg, 0.0);
  EXPECT_GT(place.summary[0].std_error_deg, 0.0);
  for (const LaunchHit& h : torque.hits) EXPECT_EQ(h.ball_start[1], 0.0);

  LaunchStudyOptions two = small(0.01, 0.001);
  two.angles_deg = {0.0, 5.0};
  two.hits = 1;
  const auto r = run_launch_study(rig().system, two);
  ASSERT_EQ(r.hits.size(), 2u);
  EXPECT_EQ(r.hits[0].seed, derive_seed(derive_seed(1, 0), 0));
  EXPECT_EQ(r.hits[1].seed, derive_seed(derive_seed(1, 1), 0));
  const auto first = run_launch_study(rig().system, small(0.01, 0.001));
  EXPECT_TRUE(same_bits(r.hits[0].launch_angle, first.hits[0].launch_angle));
}

TEST(LaunchStudy, CsvHasOneRowPerHitAndMarkdownOneRowPerAngle) {
  LaunchStudyOptions o = small(0.01, 0.001);
  o.angles_deg = {-10.0, 10.0};
  o.hits = 2;
  const auto r = run_launch_study(rig().system, o);
  print(r);
  ASSERT_EQ(r.summary.size(), 2u);
  for (const auto& s : r.summary) {
    EXPECT_EQ(s.n, 2);
    EXPECT_LT(std::abs(s.mean_error_deg), 2.0) << s.commanded_angle_deg;
  }
  std::istringstream csv(launch_study_csv(r));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "angle_deg,hit,seed,struck,ball_x,ball_y,club_angle,club_speed,launch_angle,"
            "launch_speed,launch_error_deg,club_speed_error,launch_club_ratio,faulted");
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_EQ(line.rfind(rows <= 2 ? "-10," : "10,", 0), 0u) << line;
  }
  EXPECT_EQ(rows, 4);
  const std::string md = launch_study_markdown(r);
  EXPECT_NE(md.find("| -10 | 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 10 | 2 |"), std::string::npos) << md;
}

TEST(LaunchStudy, SummaryStatistics) {
  std::vector<LaunchHit> hits(4);
  const double errors[] = {1.0, 3.0, 0.5, 0.0};
  for (int i = 0; i < 4; ++i) {
    hits[i].angle_index = i < 2 ? 0 : 1;
    hits[i].hit = i != 3;
    hits[i].launch_error_deg = errors[i];
    hits[i].club_speed_error = 0.1 * i;
    hits[i].launch_club_ratio = 0.9;
  }
  const auto s = summarize_launch_hits({-10.0, 10.0}, 1.0, hits);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].n, 2);
  EXPECT_DOUBLE_EQ(s[0].mean_error_deg, 2.0);
  EXPECT_DOUBLE_EQ(s[0].std_error_deg, std::sqrt(2.0));
  EXPECT_NEAR(s[0].mean_club_speed_error_pct, 5.0, 1e-12);
  EXPECT_EQ(s[0].std_launch_club_ratio, 0.0);
  EXPECT_EQ(s[1].n, 1);
  EXPECT_EQ(s[1].missed, 1);
  EXPECT_EQ(s[1].std_error_deg, 0.0);
}

TEST(LaunchStudy, BadOptionsAreInputErrors) {
  LaunchStudyOptions o;
  o.hits = 0;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.angles_deg.clear();
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.torque_noise = -0.1;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.placement_noise = std::nan("");
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.speed = 0.0;
  EXPECT_THROW(o.validate(), InputError);
  EXPECT_NO_THROW(LaunchStudyOptions{}.validate());
}

}  // namespace
}  // namespace mg::experiments
