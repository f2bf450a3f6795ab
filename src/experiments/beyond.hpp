#pragma once
/// The "beyond the thesis" part of `minigolf reproduce` for one field: learning curves
/// of the self-taught robot and its baselines against their own full-system putts, the goal check,
/// the hindsight labels' precision, and success under perception and execution noise.
#include <functional>
#include <map>
#include <string>

#include "field/situations.hpp"
#include "learning/learner.hpp"
#include "system/system.hpp"
#include "teacher/teacher.hpp"

namespace mg::experiments {

struct BeyondOptions {
  bool quick = false;
  int threads = 0;
  std::uint64_t seed = 1;
  int test_situations = 200;  ///< the goal check's test situations
  teacher::TeacherOptions teacher;
  std::function<std::string(const std::string&)> csv_path;  ///< file name -> path
  std::function<std::string(const std::string&)> fig_path;
  std::function<void(const std::string&, const std::string&)> plot;  ///< plot.py arguments, PNG
  std::function<void(const std::string&)> say;                       ///< progress lines
};

/// Markdown rows of the field's results, by table: "curves", "goal", "hindsight", "noise", and
/// "figures" (image links). `teacher_models`: the teacher-trained learners by method.
std::map<std::string, std::string> beyond_thesis(
    const system::System& system, const std::string& name, const field::Situations& region,
    const std::map<std::string, learning::Model>& teacher_models, const BeyondOptions& options);

}  // namespace mg::experiments
