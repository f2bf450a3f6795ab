// Worlds on many threads: built concurrently, stepped concurrently (one mjData per thread, some
// sharing a World), with exactly the bits of the same putts run serially.
#include <array>
#include <cmath>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "field/field.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"

namespace mg::sim {
namespace {

const std::array<const char*, 4> kFields{"flat", "multiple-hills", "regular-hill", "arctan"};

struct Bits {
  PuttOutcome outcome;
  std::vector<mjtNum> qpos;  // the whole final state of the ball
};

// Three putts on the field's hole; the last one passes close to it.
std::vector<Bits> putts(const World& world, mjData* d) {
  std::vector<Bits> out;
  const auto hole = world.field().hole.position;
  const auto& tee = world.field().tee;
  const double aim = std::atan2(hole[1] - tee[1], hole[0] - tee[0]);
  for (const auto& [da, v] : {std::pair{0.05, 1.2}, std::pair{-0.1, 2.5}, std::pair{0.0, 2.0}}) {
    PuttRequest q;
    q.angle = aim + da;
    q.speed = v;
    q.max_duration = 4.0;
    Bits b;
    b.outcome = simulate_putt(world, d, hole, q);
    b.qpos.assign(d->qpos, d->qpos + world.model()->nq);
    out.push_back(b);
  }
  return out;
}

void expect_same(const std::vector<Bits>& a, const std::vector<Bits>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].outcome.sunk, b[i].outcome.sunk) << what << " putt " << i;
    EXPECT_EQ(a[i].outcome.end, b[i].outcome.end) << what << " putt " << i;
    EXPECT_EQ(a[i].outcome.steps, b[i].outcome.steps) << what << " putt " << i;
    EXPECT_EQ(a[i].outcome.rest_position, b[i].outcome.rest_position) << what << " putt " << i;
    EXPECT_EQ(a[i].outcome.closest_approach, b[i].outcome.closest_approach)
        << what << " putt " << i;
    EXPECT_EQ(a[i].qpos, b[i].qpos) << what << " putt " << i;
  }
}

TEST(Threads, WorldsBuiltAndSteppedConcurrentlyGiveTheSerialBits) {
  // Serial reference.
  std::vector<std::vector<Bits>> serial;
  for (const char* name : kFields) {
    const World world(field::load_field(name));
    auto d = world.make_data();
    serial.push_back(putts(world, d.get()));
  }
  // Two threads per field: each builds its own world at the same time as all the others.
  constexpr int kPerField = 2;
  std::vector<std::vector<Bits>> parallel(kFields.size() * kPerField);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < parallel.size(); ++i)
    threads.emplace_back([&parallel, i] {
      const World world(field::load_field(kFields[i / kPerField]));
      auto d = world.make_data();
      parallel[i] = putts(world, d.get());
    });
  for (auto& t : threads) t.join();
  for (std::size_t i = 0; i < parallel.size(); ++i)
    expect_same(serial[i / kPerField], parallel[i],
                std::string("own world, ") + kFields[i / kPerField]);
}

TEST(Threads, OneWorldSharedByThreadsWithOwnData) {
  const World world(field::load_field("multiple-hills"));
  auto d0 = world.make_data();
  const auto serial = putts(world, d0.get());
  std::vector<std::vector<Bits>> parallel(4);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < parallel.size(); ++i)
    threads.emplace_back([&world, &parallel, i] {
      auto d = world.make_data();
      parallel[i] = putts(world, d.get());
    });
  for (auto& t : threads) t.join();
  for (const auto& p : parallel) expect_same(serial, p, "shared world");
}

}  // namespace
}  // namespace mg::sim
