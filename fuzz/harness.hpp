#pragma once
// Shared by the fuzz harnesses (issue 13): one input in, and the only acceptable failure is an
// mg::Error (a one-line message naming the problem). Any other exception escaping, a crash, a
// sanitizer report or a hang is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace mg::fuzz {

/// Runs `body` and aborts (a crash the fuzzer reports, with the input) on anything but mg::Error.
template <class F>
void expect_only_mg_errors(F&& body) {
  try {
    body();
  } catch (const mg::Error&) {
    // expected: bad input reported through the error policy
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: escaped non-mg exception: %s\n", e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "fuzz: escaped unknown exception\n");
    std::abort();
  }
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// A scratch file for parsers that read paths (heightmaps), unique per process.
std::string scratch_file(const char* suffix);

}  // namespace mg::fuzz

#define MG_FUZZ_TARGET(body_with_data_size)                                           \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    mg::fuzz::expect_only_mg_errors([&] { body_with_data_size; });                    \
    return 0;                                                                         \
  }
