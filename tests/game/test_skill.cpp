// The launch skill: the arm's bent launch relation recovered from a few putts, its inverse, and
// the club's extras interpolated per unit launch speed.
#include "game/skill.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace mg::game {
namespace {

// The arm's launch speed against club speed on flat (measured, src/game/skill.hpp), interpolated.
double arm_launch(double club) {
  const double x[] = {0.6, 0.857, 1.114, 1.371, 1.629, 1.886, 2.143, 2.4};
  const double y[] = {0.940, 1.356, 1.795, 2.243, 2.696, 3.145, 3.573, 3.944};
  int i = 0;
  while (i < 6 && club > x[i + 1]) ++i;
  const double t = (club - x[i]) / (x[i + 1] - x[i]);
  return y[i] + t * (y[i + 1] - y[i]);
}

TEST(LaunchSkill, SixPuttsRecoverTheBentRelationAndItsInverse) {
  LaunchSkill skill;
  for (int k = 0; k < 6; ++k) {
    const double club = 0.6 + (2.4 - 0.6) * (0.1 + 0.8 * k / 5.0);
    skill.add(club, 0.0, -0.006 - 0.0005 * club, arm_launch(club));
  }
  double worst = 0.0;
  for (double club = 0.8; club <= 2.2; club += 0.05)
    worst = std::max(worst, std::abs(skill.launch_speed(club) / arm_launch(club) - 1.0));
  EXPECT_LT(worst, 0.0075);
  const double club = skill.club_for(2.5, 0.6, 2.4);
  EXPECT_NEAR(skill.launch_speed(club), 2.5, 1e-6);
  EXPECT_EQ(skill.club_for(0.1, 0.6, 2.4), 0.6);  // below the envelope: its end
  EXPECT_NEAR(skill.angle_offset(1.5), -0.006 - 0.0005 * 1.5, 3e-4);
}

TEST(LaunchSkill, ClubExtrasScaleWithTheLaunchSpeed) {
  LaunchSkill skill;
  sim::ClubLaunch c;
  c.advance = 0.05, c.lift = 0.008, c.vertical_speed = 0.35, c.spin = {0.0, 10.0, 1.0};
  skill.add(1.7, 0.0, 0.0, 2.7, c);
  sim::ClubLaunch d = c;
  d.vertical_speed = 0.20;
  skill.add(1.0, 0.0, 0.0, 1.35, d);  // 0.20 / 1.35 per m/s here, 0.35 / 2.7 there
  const sim::ClubLaunch at = skill.club_launch(2.7);
  EXPECT_NEAR(at.vertical_speed, 0.35, 1e-12);
  EXPECT_NEAR(at.spin[1], 10.0, 1e-12);
  const sim::ClubLaunch beyond = skill.club_launch(5.4);  // constant per unit speed beyond
  EXPECT_NEAR(beyond.vertical_speed, 0.70, 1e-12);
  const double mid = skill.club_launch(2.025).vertical_speed / 2.025;
  EXPECT_NEAR(mid, 0.5 * (0.20 / 1.35 + 0.35 / 2.7), 1e-9);
  EXPECT_TRUE(LaunchSkill{}.club_launch(2.0).plain());
}

}  // namespace
}  // namespace mg::game
