#pragma once
// Tests too slow for the edit loop (`ctest -L quick`, under two minutes on 2 cores): in their
// suite's own run they skip, and tests/CMakeLists.txt runs them again as entries of their own with
// MINIGOLF_SLOW_TESTS set, labelled `slow` and not `quick`. The full suite runs both.
#include <cstdlib>

#include <gtest/gtest.h>

namespace mg::testing {

inline bool slow_tests_enabled() {
  const char* v = std::getenv("MINIGOLF_SLOW_TESTS");
  return v != nullptr && *v != '\0' && *v != '0';
}

}  // namespace mg::testing

#define MG_SLOW_TEST()                      \
  if (!::mg::testing::slow_tests_enabled()) \
  GTEST_SKIP() << "slow: runs as its own ctest entry (label slow; MINIGOLF_SLOW_TESTS=1)"
