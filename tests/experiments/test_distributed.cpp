// The process-to-process format of the experiments' results (system/wire.hpp,
// experiments/wire.hpp) and distributed_for in one process. Runs over several MPI processes are
// tested end to end by tests/python/test_mpi.py.
#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>

#include "experiments/wire.hpp"
#include "system/distributed.hpp"

namespace mg::experiments {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <typename T>
T round_trip(const T& value) {
  system::WireWriter w;
  w(value);
  T back{};
  system::WireReader r(w.bytes());
  r(back);
  EXPECT_TRUE(r.at_end());
  return back;
}

TEST(Wire, ASweepCellWithItsTrajectoryComesBackBitForBit) {
  SweepCell c;
  c.angle = 0.1 + 1e-17;
  c.speed = std::nextafter(1.5, 2.0);
  c.hit = false;
  c.outcome.sunk = true;
  c.outcome.end = sim::PuttEnd::kLeftLane;
  c.outcome.rest_position = {1.25, -0.3};
  c.outcome.closest_approach = std::numeric_limits<double>::quiet_NaN();
  c.outcome.approach_speed = 0.7;
  c.outcome.approach_lateral = -1e-300;
  c.outcome.approach_along = 0.02;
  c.outcome.duration = 3.5;
  c.outcome.steps = 3500;
  c.outcome.trajectory = {{0.0, 1, 2, 3, 4, 5, 6}, {0.01, 7, 8, 9, 10, 11, -0.0}};
  c.launch_angle = -0.2;
  c.launch_speed = 1.1;
  const SweepCell b = round_trip(c);
  EXPECT_TRUE(same_bits(b.angle, c.angle) && same_bits(b.speed, c.speed));
  EXPECT_EQ(b.hit, c.hit);
  EXPECT_EQ(b.outcome.sunk, true);
  EXPECT_EQ(b.outcome.end, sim::PuttEnd::kLeftLane);
  EXPECT_EQ(b.outcome.rest_position, c.outcome.rest_position);
  EXPECT_TRUE(std::isnan(b.outcome.closest_approach));
  EXPECT_TRUE(same_bits(b.outcome.approach_lateral, c.outcome.approach_lateral));
  EXPECT_EQ(b.outcome.approach_speed, 0.7);
  EXPECT_EQ(b.outcome.approach_along, 0.02);
  EXPECT_EQ(b.outcome.duration, 3.5);
  EXPECT_EQ(b.outcome.steps, 3500);
  ASSERT_EQ(b.outcome.trajectory.size(), 2u);
  EXPECT_EQ(b.outcome.trajectory[1].y, 8.0);
  EXPECT_TRUE(same_bits(b.outcome.trajectory[1].vz, -0.0));
  EXPECT_EQ(b.launch_angle, -0.2);
  EXPECT_EQ(b.launch_speed, 1.1);
}

TEST(Wire, ExamplesSituationsAndLaunchHitsComeBack) {
  teacher::Example e;
  e.hole = {2.0, 0.1};
  e.found = true;
  e.angle = 0.05, e.speed = 1.3, e.margin_angle = 0.004, e.margin_speed = 0.03;
  e.launch_angle = 0.051, e.launch_speed = 1.2, e.approach_speed = 0.4, e.full_putts = 17,
  e.ball_putts = 230;
  const teacher::Example eb = round_trip(e);
  EXPECT_EQ(eb.hole, e.hole);
  EXPECT_EQ(eb.found, true);
  EXPECT_EQ(eb.angle, e.angle);
  EXPECT_EQ(eb.speed, e.speed);
  EXPECT_EQ(eb.margin_angle, e.margin_angle);
  EXPECT_EQ(eb.margin_speed, e.margin_speed);
  EXPECT_EQ(eb.launch_angle, e.launch_angle);
  EXPECT_EQ(eb.launch_speed, e.launch_speed);
  EXPECT_EQ(eb.approach_speed, e.approach_speed);
  EXPECT_EQ(eb.full_putts, 17);
  EXPECT_EQ(eb.ball_putts, 230);

  SituationResult s;
  s.hole = {1.9, -0.05};
  s.predicted = {0.1, 1.4, 0.01, 0.02};
  s.in_envelope = false;
  s.sunk = true;
  s.outcome.steps = 12;
  s.oracle_found = true;
  s.oracle_full_putts = 9;
  s.oracle_ball_putts = 99;
  const SituationResult sb = round_trip(s);
  EXPECT_EQ(sb.hole, s.hole);
  EXPECT_EQ(sb.predicted.angle, 0.1);
  EXPECT_EQ(sb.predicted.speed_std, 0.02);
  EXPECT_EQ(sb.in_envelope, false);
  EXPECT_EQ(sb.sunk, true);
  EXPECT_EQ(sb.outcome.steps, 12);
  EXPECT_EQ(sb.oracle_found, true);
  EXPECT_EQ(sb.oracle_full_putts, 9);
  EXPECT_EQ(sb.oracle_ball_putts, 99);

  LaunchHit h;
  h.angle_index = 2, h.hit_index = 5, h.seed = 0xfedcba9876543210ull, h.hit = false,
  h.failure = "not at rest";
  h.club_angle = std::numeric_limits<double>::quiet_NaN(), h.rest_time = 1.25,
  h.ball_start = {0.001, -0.002};
  const LaunchHit hb = round_trip(h);
  EXPECT_EQ(hb.angle_index, 2);
  EXPECT_EQ(hb.hit_index, 5);
  EXPECT_EQ(hb.seed, h.seed);
  EXPECT_EQ(hb.failure, "not at rest");
  EXPECT_TRUE(std::isnan(hb.club_angle));
  EXPECT_EQ(hb.rest_time, 1.25);
  EXPECT_EQ(hb.ball_start, h.ball_start);
}

TEST(Wire, ATruncatedMessageIsAnError) {
  system::WireWriter w;
  w(std::string("a result"), 1.0);
  const std::string cut = w.bytes().substr(0, w.bytes().size() - 1);
  std::string s;
  double v = 0;
  system::WireReader r(cut);
  EXPECT_THROW(r(s, v), Error);
  const std::string length_only(8,
                                '\xff');  // a length beyond the message (the reader keeps a view)
  system::WireReader huge(length_only);
  EXPECT_THROW(huge(s), Error);
}

TEST(Distributed, OneProcessIsParallelFor) {
  ASSERT_EQ(system::process_count(), 1);  // not started by an MPI launcher
  const system::System sys(system::load_config("", "flat"));
  std::vector<SweepCell> a(6), b(6);
  std::vector<int> calls(6, 0);
  const auto job = [&](std::vector<SweepCell>& out) {
    return [&](int i, system::SystemData& d) {
      out[static_cast<std::size_t>(i)].outcome =
          system::ball_putt(sys, d, {2.0, 0.0}, 0.01 * i, 1.0 + 0.1 * i);
    };
  };
  system::distributed_for(sys, a, 2, job(a), [&](int i) { ++calls[static_cast<std::size_t>(i)]; });
  system::parallel_for(sys, 6, 1, job(b));
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(calls[static_cast<std::size_t>(i)], 1);
    EXPECT_EQ(a[static_cast<std::size_t>(i)].outcome.rest_position,
              b[static_cast<std::size_t>(i)].outcome.rest_position);
    EXPECT_EQ(a[static_cast<std::size_t>(i)].outcome.steps,
              b[static_cast<std::size_t>(i)].outcome.steps);
  }
}

}  // namespace
}  // namespace mg::experiments
