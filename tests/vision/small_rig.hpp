#pragma once
// A 320 x 240 copy of the shipped stereo rig for the display tests: a quarter of the pixels to
// render keeps them fast (and at the rig's rate on a busy machine).
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "core/io.hpp"
#include "vision/rig.hpp"

namespace mg::vision::testing {

/// The copy as a loaded rig.
inline Rig small_rig() {
  Rig rig = load_rig("stereo");
  for (auto& c : rig.cameras) c.width = 320, c.height = 240;
  return rig;
}

/// Writes the copy to `dir`/small.yaml (at `rate_hz`, 60 as shipped) and returns its path.
inline std::string write_small_rig(const std::filesystem::path& dir, int rate_hz = 60) {
  std::string small = read_text_file(data_dir() / "rigs" / "stereo.yaml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"width: 640", "width: 320"},
                                 {"height: 480", "height: 240"},
                                 {"rate_hz: 60", "rate_hz: " + std::to_string(rate_hz)}})
    for (auto at = small.find(from); at != std::string::npos; at = small.find(from, at + to.size()))
      small.replace(at, from.size(), to);
  const auto path = dir / "small.yaml";
  std::ofstream(path) << small;
  return path.string();
}

}  // namespace mg::vision::testing
