#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace mg::viz::testing {

/// Tests that open a window skip without a display (ctest runs them under xvfb-run -a too).
inline bool have_display() {
  const char* d = std::getenv("DISPLAY");
  return d && *d;
}

#define MG_NEED_DISPLAY()                  \
  if (!::mg::viz::testing::have_display()) \
  GTEST_SKIP() << "no DISPLAY: run under xvfb-run -a (ctest: viz_under_xvfb)"

inline std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("mg_viz_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace mg::viz::testing
