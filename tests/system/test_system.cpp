// The system layer: one configuration resolution, shared worlds, per-thread data.
#include "system/system.hpp"

#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "system/parallel.hpp"

namespace mg::system {
namespace {

TEST(System, ResolvesTheHittingModelFromAnyWorkingDirectory) {
  const auto cwd = std::filesystem::current_path();
  std::filesystem::current_path(std::filesystem::temp_directory_path());
  const control::ModuleConfig c = load_config("", "flat");
  std::filesystem::current_path(cwd);
  EXPECT_TRUE(std::filesystem::path(c.hitting_model).is_absolute()) << c.hitting_model;
  EXPECT_TRUE(std::filesystem::exists(c.hitting_model)) << c.hitting_model;
}

TEST(System, BadConfigurationIsAnInputError) {
  EXPECT_THROW(load_config(std::filesystem::temp_directory_path().string()),
               InputError);  // a directory
  EXPECT_THROW(System(load_config("", "no-such-field")), InputError);
  EXPECT_THROW(System(load_config("", "flat", "/no/such/model.json")), Error);
  const System s(load_config("", "flat"));
  EXPECT_THROW(s.check_request(0.7, 1.0, "putt"), InputError);
  EXPECT_THROW(s.check_request(0.0, NAN, "putt"), InputError);
  EXPECT_NO_THROW(s.check_request(0.0, 1.0, "putt"));
}

TEST(System, AFixedSpeedIsPlayedInTheBeliefAndTheOracleInTheTruth) {
  plant::Plant slow;
  slow.field.rolling_resistance_scale = 1.12;
  slow.arm.club_speed_scale = 0.97;
  const control::ModuleConfig c = load_config("", "flat");
  const field::Situation s{{0.0, 0.0}, {2.2, 0.1}};
  // No belief: the survey's fixed speed, bit for bit, whatever the plant; the oracle's rises.
  const System unaware(c, slow);
  EXPECT_EQ(believed_fixed_speed(unaware, s, 1.55), 1.55);
  const double oracle = true_fixed_speed(unaware, s, 1.55);
  EXPECT_GT(oracle, 1.55 / 0.97);
  // Believing the truth: the robot plays what the oracle plays.
  const System aware(c, slow, slow);
  EXPECT_EQ(believed_fixed_speed(aware, s, 1.55), oracle);
  EXPECT_EQ(true_fixed_speed(System(c), s, 1.55), 1.55);
}

TEST(System, AModelIsAskedAtTheHoleWhereTheRobotBelievesItIs) {
  plant::Plant off;
  off.field.hole_offset = {0.004, -0.003};
  off.arm.launch_angle_bias = 0.006;
  const control::ModuleConfig c = load_config("", "flat");
  const field::Situation s{{0.0, 0.0}, {2.2, 0.1}};
  // No belief: the situation itself, whatever the plant.
  const System unaware(c, off);
  const field::Situation same = believed_situation(unaware, s);
  EXPECT_EQ(same.hole, s.hole);
  EXPECT_EQ(same.ball, s.ball);
  // Believing the truth: the hole where it is.
  const System aware(c, off, off);
  const field::Situation at = believed_situation(aware, s);
  EXPECT_DOUBLE_EQ(at.hole[0], 2.204);
  EXPECT_DOUBLE_EQ(at.hole[1], 0.097);
  EXPECT_EQ(at.ball, s.ball);
}

TEST(System, PuttsOnManyThreadsGiveTheSerialBits) {
  const System s(load_config("", "flat"));
  const std::vector<double> angles{-0.05, 0.0, 0.03, 0.08};
  std::vector<double> serial(angles.size()), parallel(angles.size()), ball(angles.size()),
      ball_par(angles.size());
  SystemData d(s);
  for (std::size_t i = 0; i < angles.size(); ++i) {
    serial[i] = arm_putt(s, d, {2.0, 0.1}, angles[i], 1.5).outcome.rest_position[1];
    ball[i] = ball_putt(s, d, {2.0, 0.1}, angles[i], 2.4).rest_position[1];
  }
  parallel_for(s, static_cast<int>(angles.size()), 2, [&](int i, SystemData& data) {
    parallel[static_cast<std::size_t>(i)] =
        arm_putt(s, data, {2.0, 0.1}, angles[static_cast<std::size_t>(i)], 1.5)
            .outcome.rest_position[1];
    ball_par[static_cast<std::size_t>(i)] =
        ball_putt(s, data, {2.0, 0.1}, angles[static_cast<std::size_t>(i)], 2.4).rest_position[1];
  });
  EXPECT_EQ(serial, parallel);
  EXPECT_EQ(ball, ball_par);
}

TEST(System, AJobsExceptionReachesTheCaller) {
  const System s(load_config("", "flat"));
  EXPECT_THROW(parallel_for(s, 8, 2,
                            [](int i, SystemData&) {
                              if (i == 5) throw InputError("job 5");
                            }),
               InputError);
}

}  // namespace
}  // namespace mg::system
