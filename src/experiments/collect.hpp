#pragma once
/// Collects a data set with the teacher (`minigolf collect`): one example per situation of the
/// region, in a CSV file that is rewritten atomically after every finished situation, so an
/// interrupted run (Ctrl-C, kill) keeps every verified example, and `resume` continues it.
///
/// File: a first comment line with the run's settings (checked on resume), a header, one row per
/// found example (index order), and `# unplayable: ...` comment lines for situations where the
/// teacher found nothing. Comment lines are skipped by every CSV reader of the project, so the
/// file trains as it is: columns index,hole_x,hole_y,xi_x,xi_y,angle,speed,margin_angle,
/// margin_speed,launch_angle,launch_speed,approach_speed,full_putts,ball_putts.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "system/system.hpp"
#include "teacher/teacher.hpp"

namespace mg::experiments {

struct CollectOptions {
  teacher::TeacherOptions teacher;
  std::uint64_t seed = 1;  ///< recorded (the teacher itself is deterministic)
  int threads = 0;
  bool resume = false;     ///< continue the file at `out` (its settings must match)
};

struct CollectResult {
  std::vector<teacher::Example> examples;  ///< index order, found or not
  int resumed = 0;                         ///< situations taken from the existing file
  int full_putts = 0, ball_putts = 0;      ///< over all situations, resumed ones included
};

/// `progress(done, total, example)` after each situation (completion order).
CollectResult collect(const system::System& system, const std::vector<std::array<double, 2>>& holes,
                      const CollectOptions& options, const std::filesystem::path& out,
                      const std::function<void(int, int, const teacher::Example&)>& progress = {});

/// The settings line (without the leading "# ") for a run; exposed for tests.
std::string collect_settings(const system::System& system, const std::vector<std::array<double, 2>>& holes,
                             const CollectOptions& options);

}  // namespace mg::experiments
