#pragma once
/// Runs independent jobs (putts, situations) on a pool of threads, one `SystemData` per thread.
/// Results are stored by job index, so they are the same bits whatever the thread count; every
/// job must depend on its index only (seed per job: derive_seed(run seed, index)).
#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "system/system.hpp"

namespace mg::system {

/// Processes of this run on this machine (MPI, system/distributed.hpp; 1 without).
int local_process_count();

/// Threads to use: `requested` if > 0, else all cores (shared by the run's processes on this
/// machine).
inline int thread_count(int requested) {
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / local_process_count());
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
