#pragma once
/// A bounded single-producer single-consumer queue without locks or allocation after construction
/// (a ring of `Capacity` slots, Capacity a power of two). One thread pushes, one thread pops; the
/// pushed value happens-before its pop (release/acquire). Real-time safe on both ends as long as
/// copying a T is. Several consumers (or producers) must take turns under a lock of their own.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace mg {

template <class T, std::size_t Capacity>
class SpscQueue {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0,
                "SpscQueue: the capacity must be a power of two");

 public:
  SpscQueue() : slots_(std::make_unique<std::array<T, Capacity>>()) {}
  SpscQueue(const SpscQueue&) = delete;
  SpscQueue& operator=(const SpscQueue&) = delete;

  /// Producer: copies `value` in; false (and nothing changes) when full.
  bool push(const T& value) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_.load(std::memory_order_acquire) == Capacity) return false;
    (*slots_)[tail & (Capacity - 1)] = value;
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }
  /// Consumer: copies the oldest value out; false when empty.
  bool pop(T& out) noexcept {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_.load(std::memory_order_acquire)) return false;
    out = (*slots_)[head & (Capacity - 1)];
    head_.store(head + 1, std::memory_order_release);
    return true;
  }
  /// Either side: values waiting (a snapshot).
  std::size_t size() const noexcept {
    return static_cast<std::size_t>(tail_.load(std::memory_order_acquire) -
                                    head_.load(std::memory_order_acquire));
  }
  bool empty() const noexcept { return size() == 0; }
  static constexpr std::size_t capacity() { return Capacity; }

 private:
  std::unique_ptr<std::array<T, Capacity>> slots_;
  alignas(64) std::atomic<std::uint64_t> head_{0};  ///< next to pop (the consumer's)
  alignas(64) std::atomic<std::uint64_t> tail_{0};  ///< next to push (the producer's)
};

}  // namespace mg
