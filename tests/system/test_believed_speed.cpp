// An angle-only model's club speed in a belief (system/believed_speed.hpp): the same bits without
// a belief, and the robot's own arm model launching the ball as the speed choice assumes.
#include "system/believed_speed.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "belief/speed_choice.hpp"
#include "plant/plant.hpp"
#include "system/putt.hpp"
#include "system/system.hpp"

namespace mg::system {
namespace {

TEST(BelievedSpeed, TheArmModelLaunchesAsTheSpeedChoiceAssumes) {
  const System sys(load_config("", "flat"));
  SystemData data(sys);
  for (const double speed : {1.5, 1.8})
    for (const double angle : {-0.1, 0.0, 0.1}) {
      const auto r = arm_putt(sys, data, {2.0, 0.1}, angle, speed, {});
      ASSERT_TRUE(r.hit) << speed << " " << angle;
      EXPECT_NEAR(r.launch.speed / speed / belief::kArmLaunchPerCommand, 1.0, 0.03)
          << speed << " " << angle;
      EXPECT_NEAR(r.launch.angle - angle, belief::kArmLaunchAngleOffset, 0.0015)
          << speed << " " << angle;
    }
}

TEST(BelievedSpeed, WithoutABeliefTheSpeedIsKeptAndWithOneItIsChosen) {
  const auto config = load_config("", "flat");
  const System nominal(config);
  const field::Situation s{nominal.field().tee, {2.0, 0.1}};
  for (const double v : {1.3, 1.55, 1.9}) EXPECT_EQ(believed_club_speed(nominal, s, v, 0.05), v);
  // A slower green believed: at the equivalent speed's edge the choice moves into the window.
  const plant::Plant slow = plant::parse_plant(
      "format_version: 1\nfield: {rolling_resistance_scale: 1.15}\n", "test belief");
  const System believing(config, plant::Plant{}, slow);
  const double angle = std::atan2(0.1, 2.0);
  const double v = believed_club_speed(believing, s, 1.55, angle);
  EXPECT_NE(v, 1.55);
  EXPECT_EQ(believed_club_speed(believing, s, 1.55, angle), v);  // deterministic
  EXPECT_GE(v, config.speed_min);
  EXPECT_LE(v, std::min(config.speed_max, believing.module().club_speed_cap()));
}

}  // namespace
}  // namespace mg::system
