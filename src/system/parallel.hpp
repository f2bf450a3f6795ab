#pragma once
/// Runs independent jobs (putts, situations) on a pool of threads, one `SystemData` per thread.
/// Results are stored by job index, so they are the same bits whatever the thread count; every
/// job must depend on its index only (seed per job: derive_seed(run seed, index)).
#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <string_view>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "system/system.hpp"

namespace mg::system {

/// The default thread count (system/distributed.cpp): the cores this process may run on (its CPU
/// affinity: taskset, Slurm, mpirun --bind-to), shared with the run's other processes on this
/// machine when they are not bound to their own cores.
int default_thread_count();

/// The most threads a user may ask for (the CLI's --threads 0..256, Python's threads=).
inline constexpr int kMaxThreads = 256;

/// Throws InputError naming `what` unless 0 <= threads <= kMaxThreads (0: all cores).
inline void check_threads(int threads, std::string_view what = "threads") {
  if (threads < 0 || threads > kMaxThreads)
    throw InputError(
        fmt::format("{}: expected 0..{} (0: all cores), got {}", what, kMaxThreads, threads));
}

/// Threads to use: `requested` if > 0, else default_thread_count(). Throws InputError for a
/// request outside 0..kMaxThreads.
inline int thread_count(int requested) {
  check_threads(requested);
  return requested > 0 ? requested : default_thread_count();
}

/// True while this thread runs a job of parallel_for: a distributed_for inside a job runs locally
/// (the outer loop is the one split over processes, or duplicated on each).
inline bool& inside_parallel_job() {
  thread_local bool inside = false;
  return inside;
}

/// Calls job(i, data) for i in [0, n) on `threads` threads; `done(i)` (optional) is called after
/// each job under a lock, in completion order (progress, incremental saving). The first exception
/// thrown by a job stops the pool and is rethrown here.
template <typename Job>
void parallel_for(const System& system, int n, int threads, Job job,
                  const std::function<void(int)>& done = {}) {
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex mutex;
  const auto worker = [&] {
    const bool was_inside = inside_parallel_job();
    inside_parallel_job() = true;
    struct Restore {
      bool value;
      ~Restore() { inside_parallel_job() = value; }
    } restore{was_inside};
    try {
      SystemData data(system);
      for (int i = next++; i < n && !failed; i = next++) {
        job(i, data);
        if (done) {
          std::lock_guard lock(mutex);
          done(i);
        }
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      if (!error) error = std::current_exception();
      failed = true;
    }
  };
  const int t = std::clamp(threads, 1, std::max(1, n));
  if (t == 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (int k = 0; k < t; ++k) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace mg::system
