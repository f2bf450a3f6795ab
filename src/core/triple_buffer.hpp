#pragma once
/// The latest value from one writer thread to one reader thread, without locks or allocation after
/// construction (a triple buffer: the writer fills its back buffer and swaps it with the middle
/// one; the reader swaps the middle one with its front buffer when it holds something newer). The
/// writer never waits for the reader and the reader never sees a half-written value. Real-time
/// safe on both ends as long as filling a T is. Several readers must take turns under a lock of
/// their own (the writer never takes it).
#include <array>
#include <atomic>
#include <cstdint>

namespace mg {

template <class T>
class TripleBuffer {
 public:
  /// Every buffer starts as `initial` (sizes its members, e.g. vectors, once).
  explicit TripleBuffer(const T& initial = T{}) : buffers_{initial, initial, initial} {}
  TripleBuffer(const TripleBuffer&) = delete;
  TripleBuffer& operator=(const TripleBuffer&) = delete;

  /// Writer: the buffer to fill (its previous contents are an older value).
  T& back() noexcept { return buffers_[back_]; }
  /// Writer: makes the back buffer the latest value.
  void publish() noexcept {
    const std::uint8_t old =
        middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = old & kIndex;
  }
  /// Reader: the latest published value (the initial one before any publish). Stays valid and
  /// unchanged until the reader's next call.
  const T& read() noexcept {
    if (middle_.load(std::memory_order_relaxed) & kFresh) {
      const std::uint8_t old = middle_.exchange(front_, std::memory_order_acq_rel);
      front_ = old & kIndex;
    }
    return buffers_[front_];
  }

 private:
  static constexpr std::uint8_t kIndex = 3;
  static constexpr std::uint8_t kFresh = 4;
  std::array<T, 3> buffers_;
  std::uint8_t back_ = 0;                ///< the writer's
  std::atomic<std::uint8_t> middle_{1};  ///< index | kFresh once published and not yet read
  std::uint8_t front_ = 2;               ///< the reader's
};

}  // namespace mg
