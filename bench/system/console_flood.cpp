// Deadline misses of the real-time console's core loop under a console flood: a user thread sends
// 1,000 commands per second (`status`, `angle`, `speed`, `rest`, a `hit` a second, a recording
// started and written every 2 s) while the arm goes to the rest pose and hits. One Markdown row per
// run, and a quiet run (no commands but the hits) for comparison. A benchmark, not a test: on a
// shared or virtual machine the misses move with what else runs on the host; run it next to the
// build it is compared with, interleaved.
//
//   ./build/bench/system/console_flood [SECONDS] [RUNS]   (default 5 s, 3 runs; root: SCHED_FIFO)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <string>
#include <thread>

#include "system/session.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Run {
  unsigned long long ticks = 0, misses = 0;
  double p99 = 0.0, max = 0.0;
  long commands = 0;
  double seconds = 0.0;
};

Run run(double seconds, bool flood, const std::string& record_path) {
  std::ostream null(nullptr);  // answers discarded: the flood measures the core, not the terminal
  mg::system::SessionOptions options;
  options.realtime = true;
  Run r;
  {
    mg::system::Session session(mg::control::ModuleConfig{}, options, null);
    const char* cycle[] = {"status",    "angle 0.1", "speed 1.2", "rest",      "angle 0.05",
                           "speed 1.0", "status",    "angle 0.0", "speed 0.8", "rest"};
    const auto start = Clock::now();
    auto next = start;
    long k = 0;
    while (Clock::now() - start < std::chrono::duration<double>(seconds)) {
      std::string line;
      if (k % 1000 == 0) {
        line = "hit";
      } else if (k % 2000 == 500) {
        line = "record on " + record_path;
      } else if (k % 2000 == 1500) {
        line = "record off";
      } else if (flood) {
        line = cycle[k % 10];
      }
      if (!line.empty()) {
        session.execute(line);
        ++r.commands;
      }
      ++k;
      next += std::chrono::milliseconds(1);  // 1,000 a second; behind schedule: no sleep
      std::this_thread::sleep_until(next);
    }
    r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    session.execute("record off");
    r.ticks = session.core_ticks();
    r.misses = session.deadline_misses();
    const auto t = session.timing();
    r.p99 = t.core_update_p99_us;
    r.max = t.core_update_max_us;
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 5.0;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 3;
  if (!(seconds >= 1.0 && seconds <= 600.0) || runs < 1 || runs > 100) {
    std::fprintf(stderr, "console_flood: expected SECONDS in [1, 600] and RUNS in [1, 100]\n");
    return 2;
  }
  const std::string record_path =
      (std::filesystem::temp_directory_path() / "minigolf_console_flood.csv").string();
  std::printf(
      "| run | commands/s | core ticks | deadline misses | misses %% | core update p99 [us] | "
      "max [us] |\n|---|---|---|---|---|---|---|\n");
  for (int i = 0; i < runs; ++i) {
    for (const bool flood : {false, true}) {
      const Run r = run(seconds, flood, record_path);
      std::printf(
          "| %d %s | %.0f | %llu | %llu | %.2f | %.1f | %.0f |\n", i + 1, flood ? "flood" : "quiet",
          static_cast<double>(r.commands) / r.seconds, r.ticks, r.misses,
          r.ticks ? 100.0 * static_cast<double>(r.misses) / static_cast<double>(r.ticks) : 0.0,
          r.p99, r.max);
      std::fflush(stdout);
    }
  }
  std::filesystem::remove(record_path);
  return 0;
}
