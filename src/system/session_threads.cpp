// The session's real-time scheduler: the core thread (the core loop at 500 Hz on the wall clock,
// nothing shared with the console but lock-free channels) and the I/O thread (the vision feed,
// the vision simulator, the recorder's ring, printing).
#include <pthread.h>
#include <sched.h>

#include <array>
#include <chrono>
#include <tuple>

#include "system/session.hpp"
#include "system/session_core.hpp"

namespace mg::system {

namespace {

using Clock = std::chrono::steady_clock;

/// Tries SCHED_FIFO at `priority`; the priority the thread got (-1: none, no permission).
int set_thread_priority(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0 ? priority : -1;
}

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

}  // namespace

void Session::core_thread() {
  core_priority_ = set_thread_priority(80);
  // From here on: no allocation, no lock, no I/O (SessionCore's contract).
  const Clock::duration period = seconds(config_.core_period());
  const int streak_limit = config_.overrun_streak_limit;
  auto due = Clock::now();
  int streak = 0;
  while (!stop_.load(std::memory_order_relaxed)) {
    due += period;
    std::this_thread::sleep_until(due);
    core_->apply_queued();
    core_->tick();
    const auto done = Clock::now();
    if (done > due + period) {
      deadline_misses_.fetch_add(1, std::memory_order_relaxed);
      if (++streak >= streak_limit) core_->overrun_streak();
      // Behind by more than a period: skip the missed ticks instead of bursting to catch up.
      if (done > due + 2 * period) due = done - period;
    } else {
      streak = 0;
    }
  }
}

void Session::io_thread() {
  io_priority_ = set_thread_priority(60);
  const Clock::duration period = seconds(config_.core_period() * config_.robot_update_divider);
  auto due = Clock::now();
  while (!stop_.load(std::memory_order_relaxed)) {
    due += period;
    std::this_thread::sleep_until(due);
    if (network_) {
      // The vision simulator sees the truth the core published; the feed's answer goes to the
      // core's robot update through its buffer, stamped with the simulated time it was taken at.
      const auto [now, ball, hole] = read_snapshot([](const Snapshot& s) {
        return std::tuple<double, std::array<double, 3>, std::array<double, 3>>{s.time, s.ball,
                                                                                s.hole};
      });
      StampedPerception& out = core_->vision.back();
      {
        std::lock_guard lock(io_mutex_);
        if (publisher_) publisher_->update(now, ball, hole);
        out.seen = network_->perceive(now);
      }
      out.stamp = now;
      core_->vision.publish();
    }
    drain_samples();
    print_events();
    if (Clock::now() > due + period) due = Clock::now();
  }
}

}  // namespace mg::system
