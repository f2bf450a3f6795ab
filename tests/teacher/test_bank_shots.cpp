// Bank shots: paths folded at borders and obstacle faces, checked against the mirror law and
// against ball-only putts in the MuJoCo world.
#include "teacher/bank_shots.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

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
  - {type: block, center: [1.0, 0.0], size: [0.3, 0.5], restitution: 0.6}
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

TEST(BankShots, OneBounceFollowsTheMirrorLaw) {
  const field::Field f = field::load_field("bank-shot");
  const std::array<double, 2> hole{2.0, 0.0};
  const auto banks = bank_shots(f, f.tee, hole, 0.4);
  ASSERT_FALSE(banks.empty());
  const double r = f.ball.radius;
  // Off the +-y borders (their faces a ball radius in): the hole's images at y = +-2 (0.6 - r).
  const double image_y = 2.0 * (0.6 - r);
  const auto off = [&](double sign) {
    return std::find_if(banks.begin(), banks.end(), [&](const BankShot& b) {
      return b.bounces == 1 && std::abs(b.angle - std::atan2(sign * image_y, 2.0)) < 1e-9;
    });
  };
  ASSERT_NE(off(1.0), banks.end());
  ASSERT_NE(off(-1.0), banks.end());
  EXPECT_NEAR(off(1.0)->path_length, std::hypot(2.0, image_y), 1e-9);
  EXPECT_NEAR(off(1.0)->lateral_gain(), off(1.0)->path_length, 1e-12);  // one bounce: mirrored
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

TEST(BankShots, AWallFaceIsAMirrorAndThePhysicsAgrees) {
  const field::Field f = walled_lane();
  const std::array<double, 2> hole{2.0, 0.0};
  const auto banks = bank_shots(f, f.tee, hole, 0.4);
  const double r = f.ball.radius;
  // The wall's lower face (y = 0.38) a ball radius out.
  const double image_y = 2.0 * (0.38 - r);
  const auto wall = std::find_if(banks.begin(), banks.end(), [&](const BankShot& b) {
    return b.bounces == 1 && std::abs(b.angle - std::atan2(image_y, 2.0)) < 1e-9;
  });
  ASSERT_NE(wall, banks.end());
  // The +y border's bank crosses the wall: not proposed.
  for (const auto& b : banks)
    EXPECT_GT(std::abs(b.angle - std::atan2(2.0 * (0.6 - r), 2.0)), 1e-6) << b.angle;
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
  const system::System s(system::load_config("", "l-shape"));
  const BankShot& b = banks.front();
  EXPECT_LT(nearest_pass(s, hole, b.angle, 0.8 * b.launch_speed, 1.6 * b.launch_speed), 0.06);
}

}  // namespace
}  // namespace mg::teacher
