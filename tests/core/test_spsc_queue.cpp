// The single-producer single-consumer queue between the console and the real-time core.
#include "core/spsc_queue.hpp"

#include <cstdint>
#include <thread>

#include <gtest/gtest.h>

namespace mg {
namespace {

TEST(SpscQueue, FirstInFirstOutUpToItsCapacity) {
  SpscQueue<int, 4> q;
  int out = 0;
  EXPECT_FALSE(q.pop(out));
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(q.push(i));
  EXPECT_FALSE(q.push(99));  // full: nothing changes
  EXPECT_EQ(q.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(q.pop(out));
    EXPECT_EQ(out, i);
  }
  EXPECT_TRUE(q.empty());
  for (int round = 0; round < 10; ++round) {  // wraps around its ring
    EXPECT_TRUE(q.push(round));
    ASSERT_TRUE(q.pop(out));
    EXPECT_EQ(out, round);
  }
}

// Two threads: every value arrives once, in order (run under ThreadSanitizer too).
TEST(SpscQueue, TwoThreadsPassEveryValueInOrder) {
  struct Item {
    std::uint64_t seq = 0;
    std::uint64_t check = 0;
  };
  SpscQueue<Item, 64> q;
  constexpr std::uint64_t kCount = 200'000;
  std::thread producer([&] {
    for (std::uint64_t i = 1; i <= kCount; ++i)
      while (!q.push({i, i * 2654435761ULL})) std::this_thread::yield();
  });
  std::uint64_t expected = 1;
  Item item;
  while (expected <= kCount) {
    if (!q.pop(item)) {
      std::this_thread::yield();
      continue;
    }
    ASSERT_EQ(item.seq, expected);
    ASSERT_EQ(item.check, expected * 2654435761ULL);
    ++expected;
  }
  producer.join();
  EXPECT_TRUE(q.empty());
}

}  // namespace
}  // namespace mg
