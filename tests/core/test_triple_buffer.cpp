// The triple buffer that publishes the real-time core's latest state.
#include "core/triple_buffer.hpp"

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>

#include <gtest/gtest.h>

namespace mg {
namespace {

TEST(TripleBuffer, TheReaderSeesTheLatestPublishedValue) {
  TripleBuffer<int> b(7);
  EXPECT_EQ(b.read(), 7);  // the initial value before any publish
  b.back() = 1;
  b.publish();
  b.back() = 2;
  b.publish();
  EXPECT_EQ(b.read(), 2);  // the latest, not the first
  EXPECT_EQ(b.read(), 2);  // unchanged without a new publish
  b.back() = 3;            // written, not published
  EXPECT_EQ(b.read(), 2);
  b.publish();
  EXPECT_EQ(b.read(), 3);
}

// Two threads: the reader never sees a half-written value, and values never go back in time
// (run under ThreadSanitizer too).
TEST(TripleBuffer, TwoThreadsNeverTearAValue) {
  struct Value {
    std::array<std::uint64_t, 16> words{};
  };
  TripleBuffer<Value> b;
  constexpr std::uint64_t kCount = 200'000;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (std::uint64_t i = 1; i <= kCount; ++i) {
      Value& v = b.back();
      for (auto& w : v.words) w = i;
      b.publish();
    }
    done = true;
  });
  std::uint64_t last = 0;
  long reads = 0;
  while (!done.load() || last < kCount) {
    const Value& v = b.read();
    const std::uint64_t first = v.words[0];
    for (const auto w : v.words) ASSERT_EQ(w, first);
    ASSERT_GE(first, last);
    last = first;
    ++reads;
  }
  writer.join();
  EXPECT_EQ(last, kCount);
  EXPECT_GT(reads, 0);
}

}  // namespace
}  // namespace mg
