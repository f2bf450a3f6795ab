#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "perception/vision_feed.hpp"

namespace mg::perception {
namespace {

VisionMessage good(std::uint64_t seq, double x = 0.5) {
  VisionMessage m;
  m.seq = seq;
  m.stamp = 0.01 * static_cast<double>(seq);
  m.ball = {x, 0.1, 0.021};
  m.hole = {2.0, -0.1, 0.0};
  return m;
}

TEST(VisionFeed, RulesPerDatagram) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  EXPECT_FALSE(feed.latest());
  EXPECT_FALSE(feed.fresh(0.0)) << "nothing received yet";
  EXPECT_TRUE(std::isinf(feed.age(0.0)));

  EXPECT_EQ(feed.offer(format_vision_message(good(5)), 1.0), FeedVerdict::kAccepted);
  EXPECT_EQ(feed.offer(format_vision_message(good(5)), 1.0), FeedVerdict::kReordered);  // repeat
  EXPECT_EQ(feed.offer(format_vision_message(good(4)), 1.0), FeedVerdict::kReordered);  // late
  EXPECT_EQ(feed.offer("{nope", 1.0), FeedVerdict::kMalformed);
  EXPECT_EQ(
      feed.offer(R"({"format":"other/1","seq":9,"stamp":0,"ball":[0,0,0],"hole":[2,0,0]})", 1.0),
      FeedVerdict::kMalformed);
  EXPECT_EQ(feed.offer(format_vision_message(good(6, 99.0)), 1.0), FeedVerdict::kOutOfRange);
  EXPECT_EQ(feed.offer(std::string(kMaxVisionMessageBytes + 1, ' '), 1.0), FeedVerdict::kTooLong);
  EXPECT_EQ(feed.offer(format_vision_message(good(7, 0.7)), 1.1), FeedVerdict::kAccepted);

  const VisionCounters expected{
      .accepted = 2, .malformed = 2, .out_of_range = 1, .reordered = 2, .too_long = 1};
  EXPECT_EQ(feed.counters(), expected);
  ASSERT_TRUE(feed.latest());
  EXPECT_EQ(feed.latest()->seq, 7u);
  EXPECT_EQ(feed.latest()->ball[0], 0.7);
  // A rejected datagram leaves the latest message and its age alone.
  EXPECT_DOUBLE_EQ(feed.age(1.25), 0.15);
}

// Found by fuzzing: one datagram with seq 2^64-1 made every later one "reordered".
TEST(VisionFeed, NoSenderCanBlindTheFeed) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  for (const char* huge : {"18446744073709551615", "9223372036854775808", "9007199254740993"}) {
    const std::string d = std::string(R"({"format":"minigolf-vision/1","seq":)") + huge +
                          R"(,"stamp":0,"ball":[0,0,0.02],"hole":[2,0,0]})";
    EXPECT_EQ(feed.offer(d, 1.0), FeedVerdict::kOutOfRange) << huge;
  }
  // The largest accepted seq, then a sender restarting from 1: rejected while the feed is fresh,
  // taken once nothing was accepted for seq_reset_after (1 s).
  EXPECT_EQ(feed.offer(format_vision_message(good(kMaxVisionSeq)), 2.0), FeedVerdict::kAccepted);
  EXPECT_EQ(feed.offer(format_vision_message(good(1)), 2.5), FeedVerdict::kReordered);
  EXPECT_EQ(feed.offer(format_vision_message(good(2)), 3.1), FeedVerdict::kAccepted);
  EXPECT_EQ(feed.offer(format_vision_message(good(3)), 3.2), FeedVerdict::kAccepted);
  EXPECT_EQ(feed.offer(format_vision_message(good(2)), 3.3), FeedVerdict::kReordered);
}

TEST(VisionFeed, FreshnessByReceiveTime) {
  VisionFeedConfig config;
  config.max_age = 0.25;  // binary-exact, so the boundary below is exact too
  VisionFeed feed(UdpReceiver("127.0.0.1", 0), config);
  ASSERT_EQ(feed.offer(format_vision_message(good(1)), 10.0), FeedVerdict::kAccepted);
  EXPECT_TRUE(feed.fresh(10.0));
  EXPECT_TRUE(feed.fresh(10.249));
  EXPECT_FALSE(feed.fresh(10.25)) << "fresh means strictly younger than max_age";
  EXPECT_FALSE(feed.fresh(11.0));
  // Rejected traffic does not refresh the feed.
  feed.offer(format_vision_message(good(1)), 11.0);
  feed.offer("garbage", 11.0);
  EXPECT_FALSE(feed.fresh(11.0));
  ASSERT_EQ(feed.offer(format_vision_message(good(2)), 11.0), FeedVerdict::kAccepted);
  EXPECT_TRUE(feed.fresh(11.05));
}

TEST(VisionFeed, ConfigIsValidated) {
  VisionFeedConfig c;
  c.max_age = 0.0;
  EXPECT_THROW(VisionFeed(UdpReceiver("127.0.0.1", 0), c), InputError);
  c.max_age = std::nan("");
  EXPECT_THROW(c.validate(), InputError);
  c = {};
  c.max_datagrams_per_poll = 0;
  EXPECT_THROW(c.validate(), InputError);
  c = {};
  c.limits.z_min = 2.0;
  EXPECT_THROW(c.validate(), InputError);
}

// End to end over loopback: every kind of traffic, exact counters, then silence.
TEST(VisionFeed, LoopbackEndToEnd) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  UdpSender tx("127.0.0.1", feed.port());
  double now = 100.0;
  EXPECT_EQ(feed.poll(now), 0) << "nothing pending: poll returns at once";

  for (std::uint64_t seq = 1; seq <= 10; ++seq)
    ASSERT_TRUE(tx.send(format_vision_message(good(seq))));
  ASSERT_TRUE(tx.send("not json at all"));
  ASSERT_TRUE(tx.send(R"({"format":"minigolf-vision/1","seq":11})"));
  ASSERT_TRUE(tx.send(format_vision_message(good(12, -40.0))));          // out of range
  ASSERT_TRUE(tx.send(std::string(kMaxVisionMessageBytes + 200, 'x')));  // too long
  ASSERT_TRUE(tx.send(format_vision_message(good(3))));                  // reordered
  ASSERT_TRUE(tx.send(format_vision_message(good(10))));                 // repeated
  ASSERT_TRUE(tx.send(format_vision_message(good(13, 1.25))));           // last good
  EXPECT_EQ(feed.poll(now), 11);
  const VisionCounters expected{
      .accepted = 11, .malformed = 2, .out_of_range = 1, .reordered = 2, .too_long = 1};
  EXPECT_EQ(feed.counters(), expected);
  ASSERT_TRUE(feed.latest());
  EXPECT_EQ(feed.latest()->seq, 13u);
  EXPECT_EQ(feed.latest()->ball, good(13, 1.25).ball);
  EXPECT_EQ(feed.latest()->hole, good(13).hole);
  EXPECT_TRUE(feed.fresh(now));

  // Silence for longer than max_age: stale, but the last position is kept.
  now += 0.25;
  EXPECT_EQ(feed.poll(now), 0);
  EXPECT_FALSE(feed.fresh(now));
  EXPECT_EQ(feed.latest()->seq, 13u);

  // A stale sender that comes back with a newer seq is fresh again at once.
  ASSERT_TRUE(tx.send(format_vision_message(good(14))));
  EXPECT_EQ(feed.poll(now), 1);
  EXPECT_TRUE(feed.fresh(now));
}

TEST(VisionFeed, PollReadsAtMostItsLimitPerCall) {
  VisionFeedConfig c;
  c.max_datagrams_per_poll = 4;
  VisionFeed feed(UdpReceiver("127.0.0.1", 0), c);
  UdpSender tx("127.0.0.1", feed.port());
  for (std::uint64_t seq = 1; seq <= 10; ++seq)
    ASSERT_TRUE(tx.send(format_vision_message(good(seq))));
  EXPECT_EQ(feed.poll(0.0), 4);
  EXPECT_EQ(feed.poll(0.0), 4);
  EXPECT_EQ(feed.poll(0.0), 2);
  EXPECT_EQ(feed.latest()->seq, 10u);
}

// Random bytes and mutated good messages over the socket: no crash, every datagram counted.
TEST(VisionFeed, RandomGarbageNeverCrashes) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  UdpSender tx("127.0.0.1", feed.port());
  Rng rng(20261123);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> length(0, 700);
  const std::string base = format_vision_message(good(1));
  int sent = 0;
  for (int round = 0; round < 20; ++round) {
    for (int i = 0; i < 50; ++i) {
      std::string d;
      if (i % 2 == 0) {
        d.resize(static_cast<std::size_t>(length(rng)));
        for (char& ch : d) ch = static_cast<char>(byte(rng));
      } else {
        d = base;  // flip a few bytes of a good message
        for (int k = 0; k < 3; ++k)
          d[static_cast<std::size_t>(byte(rng)) % d.size()] = static_cast<char>(byte(rng));
      }
      sent += tx.send(d);
    }
    feed.poll(static_cast<double>(round));
  }
  const VisionCounters& c = feed.counters();
  EXPECT_EQ(c.accepted + c.rejected(), static_cast<std::uint64_t>(sent));
  EXPECT_GT(c.rejected(), 0u);
}

TEST(VisionFeed, LimitsForAField) {
  field::Field f;
  f.bounds = {-0.3, 2.7, -0.6, 0.6};
  const VisionLimits l = vision_limits_for(f, 0.1);
  EXPECT_DOUBLE_EQ(l.bounds[0], -0.4);
  EXPECT_DOUBLE_EQ(l.bounds[1], 2.8);
  EXPECT_DOUBLE_EQ(l.bounds[2], -0.7);
  EXPECT_DOUBLE_EQ(l.bounds[3], 0.7);
  EXPECT_LT(l.z_min, -f.hole.depth) << "a ball in the cup is in range";
  EXPECT_GT(l.z_max, f.ball.radius);
}

}  // namespace
}  // namespace mg::perception
