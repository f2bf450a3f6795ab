#include <unistd.h>

#include <filesystem>
#include <string>

#include "harness.hpp"

namespace mg::fuzz {

std::string scratch_file(const char* suffix) {
  return (std::filesystem::temp_directory_path() /
          ("mg_fuzz_" + std::to_string(::getpid()) + suffix))
      .string();
}

}  // namespace mg::fuzz
