#include "system/putt.hpp"

#include <cstring>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg::system {
namespace {

const System& flat() {
  static const System s(load_config("", "flat"));
  return s;
}

// A ball-only putt is simulate_putt in the ball world, bit for bit, and its JSON carries the
// keys of `minigolf putt --ball-only --json` and no arm keys.
TEST(Putt, BallOnlyIsTheBallWorldsPuttAndItsJsonHasNoArmKeys) {
  SystemData data(flat());
  PuttSpec spec;
  spec.ball_only = true;
  spec.angle = 0.01;
  spec.speed = 1.7;
  spec.hole = std::array<double, 2>{1.5, 0.1};
  const PuttReport r = putt(flat(), data, spec);
  sim::PuttRequest q;
  q.angle = spec.angle;
  q.speed = spec.speed;
  const sim::PuttOutcome direct =
      sim::simulate_putt(flat().ball_world(), data.ball.get(), {1.5, 0.1}, q);
  EXPECT_EQ(std::memcmp(&r.outcome.rest_position, &direct.rest_position, 16), 0);
  EXPECT_EQ(r.outcome.steps, direct.steps);
  EXPECT_EQ(r.ball, flat().field().tee);
  const nlohmann::json j = putt_json(flat(), spec, r);
  for (const char* key : {"field", "hole", "ball", "angle", "speed", "sunk", "end", "rest_position",
                          "closest_approach", "duration", "steps", "plant"})
    EXPECT_TRUE(j.contains(key)) << key;
  for (const char* key : {"aim", "club", "launch", "timing"}) EXPECT_FALSE(j.contains(key)) << key;
  EXPECT_EQ(j["hole"], nlohmann::json::parse("[1.5, 0.1]"));
  EXPECT_TRUE(j["plant"].is_null());
}

// With the arm the ball is launched by the club, and the report says how.
TEST(Putt, ArmPuttReportsClubAndLaunch) {
  SystemData data(flat());
  PuttSpec spec;
  spec.angle = 0.02;
  spec.speed = 1.2;
  const PuttReport r = putt(flat(), data, spec);
  EXPECT_FALSE(r.ball_only);
  EXPECT_NEAR(r.club.speed, 1.2, 0.05);
  EXPECT_GT(r.launch.speed, 1.5);
  EXPECT_GT(r.outcome.rest_position[0], 0.5);
  const nlohmann::json j = putt_json(flat(), spec, r);
  EXPECT_EQ(j["aim"], 0.0);
  EXPECT_EQ(j["launch"]["speed"], r.launch.speed);
}

TEST(Putt, BadRequestsAreInputErrorsNamingTheQuantity) {
  SystemData data(flat());
  const auto message = [&](const PuttSpec& spec) {
    try {
      putt(flat(), data, spec);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  PuttSpec aim;
  aim.ball_only = true;
  aim.speed = 1.0;
  aim.aim = 0.3;
  EXPECT_NE(message(aim).find("aim"), std::string::npos) << message(aim);
  PuttSpec off;
  off.speed = 1.0;
  off.ball = std::array<double, 2>{9.0, 0.0};
  EXPECT_NE(message(off).find("ball"), std::string::npos) << message(off);
  PuttSpec fast;
  fast.speed = 99.0;
  EXPECT_NE(message(fast).find("putt"), std::string::npos) << message(fast);
  PuttSpec hole;
  hole.ball_only = true;
  hole.speed = 1.0;
  hole.hole = std::array<double, 2>{9.0, 0.0};
  EXPECT_NE(message(hole), "no error");
}

}  // namespace
}  // namespace mg::system
