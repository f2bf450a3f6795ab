// The automated teacher: finds sinking putts on the full system with a verified neighbourhood.
#include "teacher/teacher.hpp"

#include <algorithm>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg::teacher {
namespace {

const system::System& flat() {
  static const system::System s(system::load_config("", "flat"));
  return s;
}

TEST(Teacher, FindsASinkingPuttOnTheFlatFieldInAHandfulOfPutts) {
  system::SystemData data(flat());
  TeacherOptions o;
  o.strategy = Strategy::kMinAngle;
  o.learn_speed = false;
  o.fixed_speed = 1.55;
  const Example e = teach(flat(), data, {2.0, 0.1}, o);
  ASSERT_TRUE(e.found);
  EXPECT_LE(e.full_putts, 8);  // solve (2-4) + the two neighbours
  EXPECT_EQ(e.speed, 1.55);
  EXPECT_GT(e.margin_angle, 0.0);
  // The recorded example really sinks, and so do its neighbours (it is not a window's edge).
  for (double da : {-e.margin_angle, 0.0, e.margin_angle})
    EXPECT_TRUE(system::arm_putt(flat(), data, e.hole, e.angle + da, e.speed).outcome.sunk) << da;
  // Aimed about along xi (plus the arm's launch bias).
  EXPECT_NEAR(e.angle, std::atan2(0.1, 2.0), 0.02);
}

// A situation is (ball, hole). From a ball off the tee the base stands beside the ball
// facing as at the tee, so the example's angle is a world angle along hole - ball.
TEST(Teacher, TeachesFromABallOffTheTee) {
  system::SystemData data(flat());
  const field::Situation s{{0.4, -0.2}, {2.0, 0.1}};
  const Example e = teach(flat(), data, s, TeacherOptions{});
  ASSERT_TRUE(e.found);
  EXPECT_EQ(e.ball, s.ball);
  EXPECT_EQ(e.hole, s.hole);
  EXPECT_NEAR(e.angle, std::atan2(0.3, 1.6), 0.02);
  EXPECT_FALSE(system::hit_pose(flat(), s.ball, e.angle, e.speed).turned);
  const auto out = system::arm_hit(flat(), data, s, e.angle, e.speed).outcome;
  EXPECT_TRUE(out.sunk);
  // The same putt from the tee misses: the example is the ball's, not the tee's.
  EXPECT_FALSE(system::arm_putt(flat(), data, e.hole, e.angle, e.speed).outcome.sunk);
  // A ball off the lane is refused, naming it.
  try {
    teach(flat(), data, field::Situation{{0.4, 0.9}, {2.0, 0.1}}, TeacherOptions{});
    ADD_FAILURE() << "a ball off the lane was accepted";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("ball"), std::string::npos) << err.what();
  }
}

// From a ball at y = +0.2 the hole at y = -0.15 on the hill lies at a negative hitting angle
// that needs more club speed than the fixed arm has there (1.3 m/s): the base turns.
TEST(Teacher, AHitBeyondTheFixedArmsReachIsMadeWithTheBaseTurned) {
  const system::System sys(system::load_config("", "regular-hill"));
  system::SystemData data(sys);
  const field::Situation s{{0.0, 0.2}, {1.75, -0.15}};
  const Example e = teach(sys, data, s, TeacherOptions{});
  ASSERT_TRUE(e.found);
  EXPECT_LT(e.angle, -0.15);
  EXPECT_GT(e.speed, sys.module().club_speed_cap(e.angle));
  EXPECT_TRUE(system::hit_pose(sys, s.ball, e.angle, e.speed).turned);
  EXPECT_GT(e.margin_angle, 0.0);
  EXPECT_TRUE(system::arm_hit(sys, data, s, e.angle, e.speed).outcome.sunk);
}

TEST(Teacher, ABlockedLineIsPlayedOffABorder) {
  // bank-shot: a block between the tee and the hole; the shortest bank is off the +y border.
  const system::System sys(system::load_config("", "bank-shot"));
  system::SystemData data(sys);
  const Example e = teach(sys, data, {1.9, 0.2}, TeacherOptions{});
  ASSERT_TRUE(e.found);
  EXPECT_GT(e.angle, 0.4);  // far off the direct line (0.1 rad): towards the border
  control::FullPuttOptions o;
  o.record_interval = 0.01;
  const auto out =
      system::arm_hit(sys, data, {sys.field().tee, e.hole}, e.angle, e.speed, o).outcome;
  EXPECT_TRUE(out.sunk);
  double max_y = -1.0;
  for (const auto& p : out.trajectory) max_y = std::max(max_y, p.y);
  EXPECT_GT(max_y, 0.5);  // it went by the border (the lane's edge: 0.6)
}

TEST(Teacher, StrategiesDifferAsNamedAndAreDeterministic) {
  system::SystemData data(flat());
  TeacherOptions slow, straight;
  slow.strategy = Strategy::kMinSpeed;
  straight.strategy = Strategy::kMinAngle;
  const Example a = teach(flat(), data, {1.6, 0.2}, slow);
  const Example b = teach(flat(), data, {1.6, 0.2}, straight);
  ASSERT_TRUE(a.found);
  ASSERT_TRUE(b.found);
  EXPECT_LT(a.speed, b.speed);  // min-speed arrives slower
  EXPECT_LT(a.approach_speed, b.approach_speed);
  EXPECT_GT(a.ball_putts, 0);  // proposed on the ball-only path first
  EXPECT_TRUE(system::arm_putt(flat(), data, a.hole, a.angle, a.speed).outcome.sunk);
  EXPECT_TRUE(
      system::arm_putt(flat(), data, a.hole, a.angle, a.speed + a.margin_speed).outcome.sunk);
  EXPECT_TRUE(
      system::arm_putt(flat(), data, a.hole, a.angle, a.speed - a.margin_speed).outcome.sunk);
  const Example again = teach(flat(), data, {1.6, 0.2}, slow);
  EXPECT_EQ(again.angle, a.angle);
  EXPECT_EQ(again.speed, a.speed);
  EXPECT_EQ(again.full_putts, a.full_putts);
}

TEST(Teacher, AnUnreachableHoleIsReportedNotFound) {
  system::SystemData data(flat());
  TeacherOptions o;
  o.learn_speed = false;
  o.fixed_speed = 0.4;  // far too slow for a hole 2.5 m away
  o.max_full_putts = 8;
  const Example e = teach(flat(), data, {2.5, 0.0}, o);
  EXPECT_FALSE(e.found);
  EXPECT_LE(e.full_putts, 8 + 10);
}

TEST(Teacher, BadOptionsAndNamesAreRefused) {
  EXPECT_THROW(parse_strategy("fastest"), InputError);
  EXPECT_EQ(parse_strategy("min-angle"), Strategy::kMinAngle);
  system::SystemData data(flat());
  TeacherOptions o;
  o.learn_speed = false;
  o.fixed_speed = 0.0;
  EXPECT_THROW(teach(flat(), data, {2.0, 0.0}, o), InputError);
  EXPECT_THROW(teach(flat(), data, {9.0, 0.0}, TeacherOptions{}), InputError);  // off the lane
}

TEST(TeacherOptions, ForARegionLearnWhatItLearnsWithItsStrategy) {
  const field::Field flat = field::load_field("flat");  // angle only at 1.55 m/s, min-angle
  const TeacherOptions t = options_for(flat.situations);
  EXPECT_FALSE(t.learn_speed);
  EXPECT_EQ(t.fixed_speed, flat.situations.speed);
  EXPECT_EQ(t.strategy, Strategy::kMinAngle);
  EXPECT_EQ(options_for(flat.situations, "min-speed").strategy, Strategy::kMinSpeed);
  EXPECT_EQ(t.max_full_putts, TeacherOptions{}.max_full_putts);
  EXPECT_TRUE(options_for(field::load_field("arctan").situations).learn_speed);
  EXPECT_THROW(options_for(flat.situations, "max-fun"), InputError);
}

}  // namespace
}  // namespace mg::teacher
