// Bank shots: paths folded at borders and obstacle faces, checked against the rebound law of a
// rolling ball (sim::rolling_rebound) and against ball-only putts in the MuJoCo world.
#include "teacher/bank_shots.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "sim/walls.hpp"
#include "system/system.hpp"

namespace mg::teacher {
namespace {

// A level lane, a block on the line from the tee to the hole, and a wall along it above the
// block: the bank off the +y border is walled off; the wall's lower face takes its place.
field::Field walled_lane() {
  return field::parse_field(R"(
format_version: 1
name: walled
lane: {bounds: [-0.3, 2.7, -0.6, 0.6]}
tee: [0.0, 0.0]
hole: {position: [2.0, 0.0], diameter: 0.108, depth: 0.06}
rolling_resistance: 0.1
obstacles:
  - {type: block, center: [1.0, 0.0], size: [0.3, 0.2], restitution: 0.6}
  - {type: wall, from: [0.3, 0.4], to: [1.7, 0.4], thickness: 0.04, restitution: 0.6}
surface:
  - {type: plane}
)",
                            "walled.yaml", ".");
}

/// The smallest distance [m] from the hole of any ball-only putt along `angle` at launch speeds
/// `lo`..`hi` (41 speeds): the folded path, played by the physics, passes the hole.
double nearest_pass(const system::System& s, std::array<double, 2> hole, double angle, double lo,
                    double hi) {
  system::SystemData d(s);
  double best = 1e9;
  for (int k = 0; k <= 40; ++k) {
    const double v = lo + (hi - lo) * k / 40.0;
    best = std::min(best, system::ball_putt(s, d, hole, angle, v).closest_approach);
  }
  return best;
}

TEST(BankShots, OneBounceFollowsTheReboundLaw) {
  const field::Field f = field::load_field("bank-shot");
  const std::array<double, 2> hole{2.0, 0.0};
  const auto banks = bank_shots(f, f.tee, hole, 0.4);
  ASSERT_FALSE(banks.empty());
  const double r = f.ball.radius;
  // Off the +-y borders (their faces a ball radius in, at |y| = Y): a rolling ball leaves a face
  // at a flatter angle than it came (sim::rolling_rebound), so the bounce point lies short of the
  // mirror law's x = 1, nearer the tee.
  const double y_face = 0.6 - r;
  const auto off = [&](double sign) {
    return std::find_if(banks.begin(), banks.end(), [&](const BankShot& b) {
      return b.bounces == 1 && std::abs(std::abs(b.angle) - 0.5 * 3.14159265358979) < 1.2 &&
             b.angle * sign > 0.0 && std::abs(std::tan(b.angle)) > 0.3;
    });
  };
  ASSERT_NE(off(1.0), banks.end());
  ASSERT_NE(off(-1.0), banks.end());
  for (double sign : {1.0, -1.0}) {
    const BankShot& b = *off(sign);
    const double x_b = y_face / std::tan(sign * b.angle);
    EXPECT_LT(x_b, 1.0);
    const double in = std::atan(x_b / y_face);
    const double out = sim::rolling_rebound(f.borders.restitution, in).angle;
    EXPECT_NEAR((hole[0] - x_b) / y_face, std::tan(out), 0.01 * std::tan(out)) << "the rebound law";
    EXPECT_NEAR(b.path_length, std::hypot(x_b, y_face) + std::hypot(hole[0] - x_b, y_face), 1e-9);
    EXPECT_NEAR(b.lateral_gain(), b.path_length, 1e-12);  // one bounce: mirrored
  }
  // One bounce first, each kind shortest first.
  for (std::size_t k = 1; k < banks.size(); ++k) {
    EXPECT_LE(banks[k - 1].bounces, banks[k].bounces);
    if (banks[k - 1].bounces == banks[k].bounces) {
      EXPECT_LE(banks[k - 1].path_length, banks[k].path_length);
    }
  }
  // The prior speed pays for the longer path and the bounce: more than the straight roll's.
  const double direct = 7.0 / 5.0 * std::sqrt(0.16 + 2.0 * 5.0 / 7.0 * 0.1 * 9.81 * 2.0);
  EXPECT_GT(off(1.0)->launch_speed, direct);
}

TEST(BankShots, AWallFaceBouncesLikeABorderAndThePhysicsAgrees) {
  const field::Field f = walled_lane();
  const std::array<double, 2> hole{2.0, 0.0};
  const auto banks = bank_shots(f, f.tee, hole, 0.4);
  const double r = f.ball.radius;
  // Every one-bounce bank upwards is off the wall's lower face (y = 0.38) a ball radius out: the
  // +y border's crosses the wall.
  const double y_face = 0.38 - r;
  const auto wall = std::find_if(banks.begin(), banks.end(), [&](const BankShot& b) {
    return b.bounces == 1 && b.angle > 0.0;
  });
  ASSERT_NE(wall, banks.end());
  const double x_b = y_face / std::tan(wall->angle);
  EXPECT_GT(x_b, 0.3);
  EXPECT_LT(x_b, 1.7);
  const double out = sim::rolling_rebound(0.6, std::atan(x_b / y_face)).angle;
  EXPECT_NEAR((hole[0] - x_b) / y_face, std::tan(out), 0.01 * std::tan(out));
  control::ModuleConfig config = system::load_config("", "flat");
  const system::System s(config, f);
  EXPECT_LT(nearest_pass(s, hole, wall->angle, 0.8 * wall->launch_speed, 1.5 * wall->launch_speed),
            0.03);
}

TEST(BankShots, TheLShapedLaneIsPlayedWithTwoBounces) {
  const field::Field f = field::load_field("l-shape");
  const auto hole = f.hole.position;
  const auto banks = bank_shots(f, f.tee, hole, 0.4);
  ASSERT_FALSE(banks.empty());
  for (const auto& b : banks) {
    EXPECT_EQ(b.bounces, 2);  // every single bounce is walled off
    EXPECT_GT(b.path_length, std::hypot(hole[0], hole[1]));
    EXPECT_LT(b.lateral_gain(), 0.0);  // mirrored twice: the direct line's sign
  }
  // Played by the physics, the rebound law aims within 0.25 m: after each bounce the ball slides
  // until it rolls again and its path bends (the teacher's search starts here; docs/physics.md).
  const system::System s(system::load_config("", "l-shape"));
  double best = 1e9;
  for (const auto& b : banks)
    best =
        std::min(best, nearest_pass(s, hole, b.angle, 0.8 * b.launch_speed, 1.6 * b.launch_speed));
  EXPECT_LT(best, 0.3);
}

}  // namespace
}  // namespace mg::teacher
