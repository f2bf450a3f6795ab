// Heightmap CSV (src/field/surface): a grid of heights read from a file.
#include <fstream>

#include "field/surface.hpp"
#include "harness.hpp"

MG_FUZZ_TARGET({
  const std::string path = mg::fuzz::scratch_file(".csv");
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  const auto h = mg::field::load_heightmap(path, {0.0, 1.0, -0.5, 0.5}, -0.1, 0.1);
  (void)h;
})
