// `minigolf vision-sim` run as a subprocess, sending to a receiver in this test.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

#include "../cli/run_command.hpp"
#include "perception/vision_feed.hpp"

namespace mg::perception {
namespace {

using mg::cli::testing::count_lines;
using mg::cli::testing::run_minigolf;

std::string to(const VisionFeed& feed) { return "--to 127.0.0.1:" + std::to_string(feed.port()); }

TEST(VisionSim, BallAtRestArrivesAndParses) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  const auto r =
      run_minigolf("vision-sim --fast --rate 100 --duration 0.5 --hole 1.5,0.1 " + to(feed));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("sent 50 "), std::string::npos) << r.out;
  EXPECT_EQ(feed.poll(0.0), 50);
  EXPECT_EQ(feed.counters().rejected(), 0u);
  ASSERT_TRUE(feed.latest());
  EXPECT_EQ(feed.latest()->seq, 50u);
  EXPECT_NEAR(feed.latest()->stamp, 0.49, 1e-12);
  EXPECT_NEAR(feed.latest()->ball[0], 0.0, 1e-9) << "flat field: tee at the origin";
  EXPECT_NEAR(feed.latest()->ball[2], 0.021335, 1e-6);
  EXPECT_EQ(feed.latest()->hole[0], 1.5);
  EXPECT_EQ(feed.latest()->hole[1], 0.1);
}

TEST(VisionSim, MovingBallMovesAlongThePutt) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  const auto r =
      run_minigolf("vision-sim --fast --rate 50 --duration 1 --angle 0 --speed 1 " + to(feed));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(feed.poll(0.0), 50);
  ASSERT_TRUE(feed.latest());
  EXPECT_GT(feed.latest()->ball[0], 0.3) << "after 1 s at 1 m/s the ball is well away from the tee";
  EXPECT_LT(std::abs(feed.latest()->ball[1]), 0.01) << "angle 0 rolls along +x";
}

TEST(VisionSim, InjectedBadMessagesAreRejectedAndCounted) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  const auto r = run_minigolf(
      "vision-sim --fast --rate 100 --duration 0.9 --inject-bad 5 --noise 0.001 " + to(feed));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 90 slots, every 5th bad: 18 bad (6 of each kind), 72 good.
  EXPECT_NE(r.out.find("bad injected 18 (6 malformed, 6 out of range, 6 repeated)"),
            std::string::npos)
      << r.out;
  feed.poll(0.0);
  const VisionCounters expected{
      .accepted = 72, .malformed = 6, .out_of_range = 6, .reordered = 6, .too_long = 0};
  EXPECT_EQ(feed.counters(), expected);
  EXPECT_EQ(feed.latest()->seq, 89u) << "slot 90 was bad";
}

TEST(VisionSim, DropoutOneSendsNothing) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  const auto r =
      run_minigolf("vision-sim --fast --rate 100 --duration 0.5 --dropout 1 " + to(feed));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("sent 0 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("dropped 50"), std::string::npos) << r.out;
  EXPECT_EQ(feed.poll(0.0), 0);
  EXPECT_EQ(feed.counters(), VisionCounters{});
}

TEST(VisionSim, DropoutIsSeededAndPartial) {
  VisionFeed a(UdpReceiver("127.0.0.1", 0));
  VisionFeed b(UdpReceiver("127.0.0.1", 0));
  const std::string args = "vision-sim --fast --rate 100 --duration 1 --dropout 0.3 --seed 7 ";
  ASSERT_EQ(run_minigolf(args + to(a)).exit_code, 0);
  ASSERT_EQ(run_minigolf(args + to(b)).exit_code, 0);
  const int na = a.poll(0.0);
  EXPECT_EQ(na, b.poll(0.0)) << "same seed, same messages";
  EXPECT_GT(na, 50);
  EXPECT_LT(na, 90);
}

TEST(VisionSim, PacedByTheWallClock) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_minigolf("vision-sim --rate 50 --duration 0.3 --latency 0.05 " + to(feed));
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The last of 15 messages is captured at 0.28 s and sent 0.05 s later.
  EXPECT_GT(elapsed, 0.32);
  EXPECT_EQ(feed.poll(0.0), 15);
}

TEST(VisionSim, BadArgumentsExitTwoWithOneLine) {
  for (const char* args :
       {"--rate 0", "--rate nan", "--rate abc", "--rate 1e9", "--noise -1", "--latency inf",
        "--dropout 1.5", "--duration 0", "--seed -3", "--inject-bad 2.5", "--to nowhere",
        "--to 127.0.0.1:0", "--to 127.0.0.1:70000", "--angle 0.1", "--speed 1",
        "--angle 0 --speed 99", "--hole 40,0", "--hole 1,x", "--field no_such_field"}) {
    const auto r = run_minigolf(std::string("vision-sim --fast ") + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << args << ": " << r.out;
  }
}

}  // namespace
}  // namespace mg::perception
