// Hindsight labels: where a path says other holes would have been sunk, checked on synthetic paths
// and against putts replayed with the hole really there.
#include "selfteach/hindsight.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "field/field.hpp"
#include "selfteach/self_teach.hpp"
#include "system/system.hpp"

namespace mg::selfteach {
namespace {

constexpr std::array<double, 2> kTee{0.0, 0.0};  // where the putts of the synthetic paths start

/// A ball along +x from (0, y0) decelerating uniformly: v(t) = v0 - a t.
std::vector<sim::BallSample> straight_path(double v0, double a, double y0 = 0.0, double dt = 0.01) {
  std::vector<sim::BallSample> t;
  for (double time = 0.0; v0 - a * time > 0.0; time += dt) {
    const double v = v0 - a * time;
    t.push_back({time, v0 * time - 0.5 * a * time * time, y0, 0.02, v, 0.0, 0.0});
  }
  return t;
}

field::Situations box(double x0, double x1, double y0, double y1) {
  field::Situations r;
  r.shape = field::RegionShape::kBox;
  r.x_range = {x0, x1};
  r.y_range = {y0, y1};
  r.counts = {2, 2};
  return r;
}

TEST(Hindsight, AngleAndSpeedLabelIsWhereTheBallSlowsToTheArrivalSpeed) {
  // v0 = 2, a = 0.5: the speed is 0.4 at t = 3.2 s, x = 2 * 3.2 - 0.25 * 3.2^2 = 3.84 m.
  const auto path = straight_path(2.0, 0.5);
  HindsightRules rules;
  rules.arrival_speed = 0.4;
  const auto far_hole = std::array<double, 2>{10.0, 5.0};
  const auto l = hindsight_labels(path, kTee, far_hole, 0.054, 0.5, box(3.0, 4.0, -0.5, 0.5), 0.1,
                                  0.1, 1.5, 7, rules);
  ASSERT_EQ(l.size(), 1u);
  EXPECT_NEAR(l[0].hole[0], 3.84, 1e-3);
  EXPECT_NEAR(l[0].hole[1], 0.0, 1e-12);
  EXPECT_NEAR(l[0].arrival_speed, 0.4, 1e-9);
  EXPECT_EQ(l[0].angle, 0.1);
  EXPECT_EQ(l[0].speed, 1.5);
  EXPECT_EQ(l[0].putt, 7);
  // Outside the region (and its margin): no label.
  EXPECT_TRUE(hindsight_labels(path, kTee, far_hole, 0.054, 0.5, box(0.0, 1.0, -0.5, 0.5), 0.1, 0.1,
                               1.5, 7, rules)
                  .empty());
  // The path ends where it met the real hole: a hole before the label point leaves no label.
  EXPECT_TRUE(hindsight_labels(path, kTee, {3.0, 0.01}, 0.054, 0.5, box(3.0, 4.0, -0.5, 0.5), 0.1,
                               0.1, 1.5, 7, rules)
                  .empty());
  // ... but a hole at the label point itself does: the free roll is continued over it.
  const auto own = hindsight_labels(path, kTee, {3.84, 0.0}, 0.054, 0.5, box(3.0, 4.0, -0.5, 0.5),
                                    0.1, 0.1, 1.5, 7, rules);
  ASSERT_EQ(own.size(), 1u);
  EXPECT_NEAR(own[0].hole[0], 3.84, 2e-3);
}

TEST(Hindsight, AngleOnlyLabelsTheCrossingOfALineOrPointsInABox) {
  const auto path = straight_path(2.0, 0.5, 0.1);
  HindsightRules rules;
  rules.learn_speed = false;
  field::Situations line;
  line.shape = field::RegionShape::kLine;
  line.from = {2.0, -0.5};
  line.to = {2.0, 0.5};
  line.count = 5;
  const auto l =
      hindsight_labels(path, kTee, {10.0, 5.0}, 0.054, 0.5, line, 0.05, 0.0, 1.0, 0, rules);
  ASSERT_EQ(l.size(), 1u);
  EXPECT_NEAR(l[0].hole[0], 2.0, 1e-9);
  EXPECT_NEAR(l[0].hole[1], 0.1, 1e-12);
  // v^2 = v0^2 - 2 a x = 4 - 2 = 2.
  EXPECT_NEAR(l[0].arrival_speed, std::sqrt(2.0), 2e-3);
  // A box 0.3 m long: a label every 3 cm of path inside it.
  rules.spacing = 0.03;
  const auto b = hindsight_labels(path, kTee, {10.0, 5.0}, 0.054, 0.5, box(2.0, 2.3, 0.0, 0.2), 0.0,
                                  0.0, 1.0, 0, rules);
  EXPECT_GE(b.size(), 8u);
  EXPECT_LE(b.size(), 10u);
  for (std::size_t i = 1; i < b.size(); ++i)
    EXPECT_GE(b[i].hole[0] - b[i - 1].hole[0], 0.03 - 1e-9);
}

TEST(Hindsight, BadRulesAreRefused) {
  HindsightRules r;
  r.arrival_speed = std::nan("");
  EXPECT_THROW(r.validate(), InputError);
  r.arrival_speed = 0.4;
  r.spacing = 0.0;
  EXPECT_THROW(r.validate(), InputError);
}

TEST(Hindsight, LabelsOfARealPuttSinkWhenReplayedWithTheHoleThere) {
  static const system::System sys(system::load_config("", "regular-hill"));
  system::SystemData data(sys);
  const auto& region = sys.field().situations;
  control::FullPuttOptions o;
  o.record_interval = 0.005;
  // A putt with the hole far off its path, then replays with the hole at its label.
  int labels = 0, sunk = 0;
  for (const double angle : {0.0, 0.05, 0.1})
    for (const double speed : {1.5, 1.55}) {
      const auto r = system::arm_putt(sys, data, {1.2, -0.3}, angle, speed, o);
      ASSERT_TRUE(r.hit);
      ASSERT_FALSE(r.outcome.trajectory.empty());
      HindsightRules rules;
      rules.arrival_speed = 0.4;
      for (const auto& l : hindsight_labels(r.outcome.trajectory, sys.field().tee, {1.2, -0.3},
                                            0.054, 0.35, region, 0.3, angle, speed, 0, rules)) {
        ++labels;
        sunk += replay_label(sys, data, l);
      }
    }
  EXPECT_GE(labels, 4);
  EXPECT_EQ(sunk, labels);
}

}  // namespace
}  // namespace mg::selfteach
