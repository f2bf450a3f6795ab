#pragma once
/// Collects a data set with the teacher (`minigolf collect`): one example per situation of the
/// region, in a CSV file that is rewritten atomically after every finished situation, so an
/// interrupted run (Ctrl-C, kill) keeps every verified example, and `resume` continues it.
///
/// File: a first comment line with the run's settings (checked on resume), a header, one row per
/// found example (index order), and `# unplayable: ...` comment lines for situations where the
/// teacher found nothing. Comment lines are skipped by every CSV reader of the project, so the
/// file trains as it is: columns index,hole_x,hole_y,xi_x,xi_y,angle,speed,margin_angle,
/// margin_speed,launch_angle,launch_speed,approach_speed,full_putts,ball_putts (xi = hole - ball),
/// and ball_x,ball_y when a ball lies off the tee (a region with a ball region).
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
  bool resume = false;  ///< continue the file at `out` (its settings must match)
};

struct CollectResult {
  std::vector<teacher::Example> examples;  ///< index order, found or not
  int resumed = 0;                         ///< situations taken from the existing file
  int repaired = 0;                        ///< examples replaced by the continuity pass
  int full_putts = 0, ball_putts = 0;      ///< over all situations, resumed ones included
};

/// After every situation is done, a continuity pass (thesis 3.2): an example whose angle relative
/// to the aim, or whose speed, jumps away from the median of its (up to 4) nearest neighbours by
/// more than kAngleJump / kSpeedJump — another strategy's window — and a situation without an
/// example are taught again from the neighbours' values (TeacherOptions::hint); the new example
/// replaces the old one if it sinks and lies closer to the neighbours. Its putts are added to the
/// example's count. The pass is deterministic (it reads the finished first pass only) and ends
/// in one atomic write.
constexpr double kAngleJump = 0.05;  ///< [rad]
constexpr double kSpeedJump = 0.1;   ///< [m/s]

/// `progress(done, total, example)` after each situation (completion order).
CollectResult collect(const system::System& system, const std::vector<field::Situation>& situations,
                      const CollectOptions& options, const std::filesystem::path& out,
                      const std::function<void(int, int, const teacher::Example&)>& progress = {});
/// The same with every ball on the tee.
CollectResult collect(const system::System& system, const std::vector<std::array<double, 2>>& holes,
                      const CollectOptions& options, const std::filesystem::path& out,
                      const std::function<void(int, int, const teacher::Example&)>& progress = {});

/// The situations of `holes` with the ball on the field's tee.
std::vector<field::Situation> on_tee(const field::Field& field,
                                     const std::vector<std::array<double, 2>>& holes);

/// The settings line (without the leading "# ") for a run; exposed for tests.
std::string collect_settings(const system::System& system,
                             const std::vector<field::Situation>& situations,
                             const CollectOptions& options);
std::string collect_settings(const system::System& system,
                             const std::vector<std::array<double, 2>>& holes,
                             const CollectOptions& options);

}  // namespace mg::experiments
