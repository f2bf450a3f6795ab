// The stroke planner: the strokes-to-go heuristic, direct sinks, bank shots round a block.
#include "game/planner.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "sim/putt.hpp"
#include "system/system.hpp"

namespace mg::game {
namespace {

constexpr double kPi = 3.14159265358979323846;

system::System system_for(const std::string& field) {
  return system::System(system::load_config("", field));
}

PlannerOptions quick() {
  PlannerOptions o;
  o.speeds = 12;
  return o;
}

TEST(Planner, StrokesToGoCountsBlockedLinesAndPenalties) {
  const field::Field f = field::load_field("bank-shot");
  EXPECT_TRUE(line_blocked(f, f.tee, f.hole.position, f.ball.radius));
  EXPECT_FALSE(line_blocked(f, {1.8, 0.4}, f.hole.position, f.ball.radius));
  const double open = strokes_to_go(f, {1.8, 0.4}, false);
  EXPECT_NEAR(open, 1.0 + 0.05 * std::hypot(0.2, 0.4), 1e-12);
  EXPECT_NEAR(strokes_to_go(f, {1.8, 0.4}, true), open + 1.0, 1e-12);
  EXPECT_GT(strokes_to_go(f, f.tee, false), 2.0);  // blocked: at least two more strokes
}

TEST(Planner, ExactExecutionSinksTheDirectPuttOnFlat) {
  const auto sys = system_for("flat");
  const auto hole = sys.field().hole.position;
  const StrokePlan p = plan_stroke(sys, sys.field().tee, hole, {}, quick());
  EXPECT_FALSE(p.bank);
  EXPECT_GE(p.sink_probability, 0.9);
  EXPECT_NEAR(p.expected_strokes, 1.0, 0.1);
  EXPECT_LT(
      std::abs(p.angle - std::atan2(hole[1] - sys.field().tee[1], hole[0] - sys.field().tee[0])),
      kDirectSpan + 1e-9);
  system::SystemData d(sys);
  const auto out = system::ball_putt(sys, d, hole, p.angle, p.speed, 0.0, sys.field().tee);
  EXPECT_TRUE(out.sunk);
}

TEST(Planner, AJudgedLaunchScoresAsThePlanAndAMissAsAMiss) {
  const auto sys = system_for("flat");
  const auto& f = sys.field();
  const LaunchError e{0.002, 0.01};
  const StrokePlan p = plan_stroke(sys, f.tee, f.hole.position, e, quick());
  const LaunchJudgement same =
      judge_launch(sys, f.tee, f.hole.position, p.angle, p.speed, e, quick());
  EXPECT_NEAR(same.sink_probability, p.sink_probability, 1e-12);
  EXPECT_NEAR(same.expected_strokes, p.expected_strokes, 1e-12);
  const LaunchJudgement wide =
      judge_launch(sys, f.tee, f.hole.position, p.angle + 0.3, p.speed, e, quick());
  EXPECT_EQ(wide.sink_probability, 0.0);
  EXPECT_GT(wide.expected_strokes, 2.0);
  EXPECT_THROW(judge_launch(sys, f.tee, f.hole.position, std::nan(""), 1.0, e, quick()),
               InputError);
}

TEST(Planner, SameBitsForAnyThreadCountAndWithTheCache) {
  const auto sys = system_for("flat");
  const auto hole = sys.field().hole.position;
  PlannerOptions one = quick(), two = quick();
  one.threads = 1;
  two.threads = 2;
  const LaunchError err{0.004, 0.02};
  const StrokePlan a = plan_stroke(sys, {1.2, 0.1}, hole, err, one);
  ImaginedCache cache;
  const StrokePlan b = plan_stroke(sys, {1.2, 0.1}, hole, err, two, &cache);
  const StrokePlan c = plan_stroke(sys, {1.2, 0.1}, hole, err, two, &cache);
  for (const StrokePlan* q : {&b, &c}) {
    EXPECT_EQ(a.angle, q->angle);
    EXPECT_EQ(a.speed, q->speed);
    EXPECT_EQ(a.expected_strokes, q->expected_strokes);
  }
  EXPECT_GT(b.imagined_putts, 0);
  EXPECT_EQ(c.imagined_putts, 0);  // every putt from the cache
}

TEST(Planner, TheBlockedLineIsPlayedRoundTheBlock) {
  const auto sys = system_for("bank-shot");
  const auto& f = sys.field();
  const StrokePlan p = plan_stroke(sys, f.tee, f.hole.position, {}, quick());
  const double direct = std::atan2(f.hole.position[1] - f.tee[1], f.hole.position[0] - f.tee[0]);
  EXPECT_TRUE(p.bank);
  EXPECT_GT(std::abs(std::remainder(p.angle - direct, 2 * kPi)), kDirectSpan);
  // The plan's own prediction holds in the world it planned in.
  system::SystemData d(sys);
  const auto out = system::ball_putt(sys, d, f.hole.position, p.angle, p.speed, 0.0, f.tee);
  if (p.sink_probability >= 0.99) {
    EXPECT_TRUE(out.sunk);
  }
  if (!out.sunk) {
    EXPECT_LT(strokes_to_go(f, out.rest_position, false), 2.0);  // a clear next putt
  }
}

TEST(Planner, AClubLaunchNextToAWallIsImaginedFromTheBall) {
  // The club's launch starts the ball 5 cm along: beside a border or a wall that point is off
  // the lane or inside the wall, and the imagined putt starts from the ball instead.
  const auto sys = system_for("l-shape");
  const auto& f = sys.field();
  PlannerOptions o = quick();
  o.club_launch = [](double u) {
    sim::ClubLaunch c;
    c.advance = 0.02 * u, c.lift = 0.003, c.vertical_speed = 0.1 * u;
    return c;
  };
  for (const std::array<double, 2> ball : {std::array<double, 2>{f.bounds[0] + 0.03, 1.75},
                                           std::array<double, 2>{1.0, 0.62 - 0.02 - 0.025}}) {
    const StrokePlan p = plan_stroke(sys, ball, f.hole.position, {0.002, 0.01}, o);
    EXPECT_TRUE(std::isfinite(p.expected_strokes));
  }
}

TEST(Planner, BadRequestsAreInputErrors) {
  const auto sys = system_for("flat");
  const auto hole = sys.field().hole.position;
  EXPECT_THROW(plan_stroke(sys, {9.0, 0.0}, hole, {}, quick()), InputError);
  EXPECT_THROW(plan_stroke(sys, sys.field().tee, hole, {0.9, 0.0}, quick()), InputError);
  EXPECT_THROW(plan_stroke(sys, sys.field().tee, hole, {std::nan(""), 0.0}, quick()), InputError);
  PlannerOptions bad = quick();
  bad.speeds = 1;
  EXPECT_THROW(plan_stroke(sys, sys.field().tee, hole, {}, bad), InputError);
  bad = quick();
  bad.speed_max = 0.1;
  EXPECT_THROW(bad.validate(), InputError);
}

}  // namespace
}  // namespace mg::game
