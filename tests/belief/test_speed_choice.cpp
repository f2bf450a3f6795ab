#include "belief/speed_choice.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "field/field.hpp"
#include "sim/fast_putt.hpp"

namespace mg::belief {
namespace {

/// Does a plain launch of `club` club speed along x from the tee sink at (1.5, 0) on flat?
bool sinks(const sim::World& world, double angle, double club) {
  sim::PuttRequest r;
  r.angle = angle;
  r.speed = kNominalLaunchPerClub * club;
  r.start = world.field().tee;
  const sim::DataPtr d = world.make_data();
  return sim::fast_putt(world, d.get(), {1.5, 0.0}, r).sunk;
}

/// The club speeds (0.5 % apart) at which a hit straight at (1.5, 0) sinks on flat.
std::array<double, 2> sinking_speeds(const sim::World& world) {
  double lo = NAN, hi = NAN;
  for (double v = 0.4; v < 2.5; v += 0.005)
    if (sinks(world, 0.0, v)) {
      if (std::isnan(lo)) lo = v;
      hi = v;
    }
  return {lo, hi};
}

TEST(SpeedChoice, AWindowsEdgeIsLeftForItsMiddle) {
  const sim::World world(field::load_field("flat"));
  const auto [lo, hi] = sinking_speeds(world);
  ASSERT_TRUE(std::isfinite(lo) && hi > 1.1 * lo) << lo << " " << hi;
  // Asked at either edge of the window, the choice moves inside it, and its neighbours 3 % either
  // way sink too; asked in the middle, it stays within the window's middle half.
  for (const double asked : {lo, hi, 0.5 * (lo + hi)}) {
    const SpeedChoice c = choose_club_speed(world, world.field().tee, {1.5, 0.0}, 0.0, asked);
    EXPECT_GT(c.club_speed, lo + 0.25 * (hi - lo)) << asked;
    EXPECT_LT(c.club_speed, hi - 0.25 * (hi - lo)) << asked;
    EXPECT_TRUE(sinks(world, 0.0, 0.97 * c.club_speed) && sinks(world, 0.0, 1.03 * c.club_speed));
    EXPECT_GT(c.score, 0.5);
    EXPECT_EQ(c.imagined_putts, 21 * 11);
    // Deterministic: the same bits again.
    EXPECT_EQ(choose_club_speed(world, world.field().tee, {1.5, 0.0}, 0.0, asked).club_speed,
              c.club_speed);
  }
}

TEST(SpeedChoice, NothingSinkingKeepsTheAskedSpeedAndTheRangeHolds) {
  const sim::World world(field::load_field("flat"));
  // Aimed 0.5 rad off the hole: nothing sinks, the asked speed stays (clamped to the range).
  EXPECT_EQ(choose_club_speed(world, world.field().tee, {1.5, 0.0}, 0.5, 1.2).club_speed, 1.2);
  SpeedChoiceOptions o;
  o.speed_max = 1.0;
  EXPECT_EQ(choose_club_speed(world, world.field().tee, {1.5, 0.0}, 0.5, 1.2, o).club_speed, 1.0);
  // A window beyond the range: the choice stays within it.
  const auto [lo, hi] = sinking_speeds(world);
  o.speed_max = lo + 0.1 * (hi - lo);
  const double v = choose_club_speed(world, world.field().tee, {1.5, 0.0}, 0.0, lo, o).club_speed;
  EXPECT_LE(v, o.speed_max);
}

TEST(SpeedChoice, AHitAlongMinusXIsImaginedAcrossPi) {
  const sim::World world(field::load_field("flat"));
  // From (2.0, 0) back to a hole at (0.5, 0) (the tee's 1.5 m mirrored): angles round pi on
  // both sides of the cut.
  const auto [lo, hi] = sinking_speeds(world);
  for (const double angle : {3.1410, -3.1410}) {
    const SpeedChoice c = choose_club_speed(world, {2.0, 0.0}, {0.5, 0.0}, angle, 0.5 * (lo + hi));
    EXPECT_GT(c.score, 0.5) << angle;
  }
}

TEST(SpeedChoice, BadOptionsAreNamed) {
  const sim::World world(field::load_field("flat"));
  SpeedChoiceOptions o;
  o.angle_sigma = NAN;
  try {
    choose_club_speed(world, world.field().tee, {1.5, 0.0}, 0.0, 1.2, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("angle_sigma"), std::string::npos) << e.what();
  }
  EXPECT_THROW(choose_club_speed(world, world.field().tee, {1.5, 0.0}, 0.0, -1.0), InputError);
  EXPECT_THROW(choose_club_speed(world, world.field().tee, {1.5, 0.0}, NAN, 1.0), InputError);
}

}  // namespace
}  // namespace mg::belief
