#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "field/field.hpp"
#include "perception/perception.hpp"
#include "sim/world.hpp"
#include "sim_backend/simulator_perception.hpp"

namespace mg::perception {
namespace {

TEST(SimulatorPerception, ReadsBallAndHoleOfAWorld) {
  const sim::World world(field::load_field("flat"));
  auto data = world.make_data();
  world.set_hole(data.get(), {1.8, 0.2});
  world.place_ball(data.get(), {0.4, -0.1});
  SimulatorPerception perception(world, data.get());
  const Perceived p = perception.perceive(123.0);
  EXPECT_TRUE(p.fresh);
  EXPECT_EQ(p.age, 0.0);
  EXPECT_DOUBLE_EQ(p.ball[0], 0.4);
  EXPECT_DOUBLE_EQ(p.ball[1], -0.1);
  EXPECT_NEAR(p.ball[2], world.field().height(0.4, -0.1) + world.field().ball.radius, 1e-12);
  EXPECT_DOUBLE_EQ(p.hole[0], 1.8);
  EXPECT_DOUBLE_EQ(p.hole[1], 0.2);
  EXPECT_NEAR(p.hole[2], world.field().height(1.8, 0.2), 1e-12);

  // It follows the simulation: a rolling ball moves, and so does what is perceived.
  data->qvel[world.ids().ball_dof] = 1.0;
  for (int i = 0; i < 100; ++i) world.step(data.get());
  EXPECT_GT(perception.perceive(0.0).ball[0], 0.45);
}

TEST(NetworkPerception, ReportsTheFeedAndItsFreshness) {
  VisionFeed feed(UdpReceiver("127.0.0.1", 0));
  NetworkPerception perception(feed);
  Perceived p = perception.perceive(0.0);
  EXPECT_FALSE(p.fresh);
  EXPECT_TRUE(std::isinf(p.age));

  UdpSender tx("127.0.0.1", feed.port());
  VisionMessage m;
  m.seq = 1;
  m.ball = {0.3, 0.05, 0.021};
  m.hole = {2.0, 0.0, 0.0};
  ASSERT_TRUE(tx.send(format_vision_message(m)));
  p = perception.perceive(5.0);  // polls the feed
  EXPECT_TRUE(p.fresh);
  EXPECT_EQ(p.ball, m.ball);
  EXPECT_EQ(p.hole, m.hole);
  EXPECT_EQ(p.age, 0.0);

  p = perception.perceive(5.5);
  EXPECT_FALSE(p.fresh) << "0.5 s of silence is stale (max_age 0.2 s)";
  EXPECT_EQ(p.ball, m.ball) << "the last position is still reported";
  EXPECT_DOUBLE_EQ(p.age, 0.5);
}

/// A source whose ball is at x = the time it was asked.
class Clock final : public Perception {
 public:
  Perceived perceive(double now) noexcept override {
    Perceived p;
    p.fresh = true;
    p.ball = {now, 0.0, 0.02};
    p.hole = {2.0, 0.0, 0.0};
    p.age = 0.0;
    return p;
  }
};

TEST(DelayedPerception, AnswersWhatItsSourceSawLatencyAgo) {
  Clock clock;
  DelayedPerception late(clock, 0.03);
  EXPECT_FALSE(late.identity());
  // Until an answer is old enough, the oldest kept.
  EXPECT_EQ(late.perceive(0.00).ball[0], 0.00);
  EXPECT_EQ(late.perceive(0.01).ball[0], 0.00);
  EXPECT_EQ(late.perceive(0.02).ball[0], 0.00);
  const Perceived p = late.perceive(0.03);
  EXPECT_EQ(p.ball[0], 0.00);
  EXPECT_DOUBLE_EQ(p.age, 0.03);
  EXPECT_EQ(late.perceive(0.04).ball[0], 0.01);
  EXPECT_EQ(late.perceive(0.05).hole, (std::array<double, 3>{2.0, 0.0, 0.0}));
  // Wrapped again, it starts afresh: no answer from before.
  late.wrap(clock);
  EXPECT_EQ(late.perceive(1.0).ball[0], 1.0);
  EXPECT_TRUE(DelayedPerception(0.0).identity());
}

TEST(OffsetPerception, MovesTheBallOnly) {
  Clock clock;
  OffsetPerception off(clock, {0.002, -0.001});
  EXPECT_FALSE(off.identity());
  const Perceived p = off.perceive(0.5);
  EXPECT_EQ(p.ball[0], 0.5 + 0.002);
  EXPECT_EQ(p.ball[1], -0.001);
  EXPECT_EQ(p.ball[2], 0.02);
  EXPECT_EQ(p.hole, (std::array<double, 3>{2.0, 0.0, 0.0}));
  EXPECT_EQ(p.age, 0.0);
  EXPECT_TRUE(OffsetPerception({0.0, 0.0}).identity());
  // A chain, as a plant's vision is (built first, bound after): late, then off.
  DelayedPerception late(0.5);
  OffsetPerception seen({0.01, 0.0});
  late.wrap(clock);
  seen.wrap(late);
  for (int k = 0; k <= 8; ++k) (void)seen.perceive(0.25 * k);
  const Perceived q = seen.perceive(2.25);
  EXPECT_EQ(q.ball[0], 1.75 + 0.01);
  EXPECT_EQ(q.age, 0.5);
}

}  // namespace
}  // namespace mg::perception
