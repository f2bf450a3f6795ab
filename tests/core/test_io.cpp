#include "core/io.hpp"

#include <filesystem>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg {
namespace {

TEST(Io, AtomicWriteReplacesAndReadsBack) {
  const auto path = std::filesystem::temp_directory_path() / "mg_io_test.txt";
  write_file_atomic(path, "first");
  write_file_atomic(path, "second");
  EXPECT_EQ(read_text_file(path), "second");
  std::filesystem::remove(path);
}

TEST(Io, MissingFileIsIoError) {
  EXPECT_THROW(read_text_file("/nonexistent/dir/file.txt"), IoError);
  EXPECT_THROW(write_file_atomic("/nonexistent/dir/file.txt", "x"), IoError);
}

}  // namespace
}  // namespace mg
