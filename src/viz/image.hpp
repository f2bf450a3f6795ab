#pragma once
/// RGB images (rows top to bottom), PNG encoding and the filmstrip of a hit's stages.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace mg::viz {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3, row 0 at the top

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0) {}
  const std::uint8_t* pixel(int x, int y) const {
    return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x);
  }
  std::uint8_t* pixel(int x, int y) {
    return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x);
  }
};

/// PNG file contents of `image` (8-bit RGB). Throws Error if libpng fails.
std::string encode_png(const Image& image);
/// Writes `image` as a PNG, atomically.
void write_png(const std::filesystem::path& path, const Image& image);
/// Reads an 8-bit RGB PNG (tests, tools). Throws IoError.
Image read_png(const std::filesystem::path& path);

/// The frames side by side, separated by `gap` pixels of `background` grey; all frames must have
/// the same size (InputError otherwise).
Image filmstrip(const std::vector<Image>& frames, int gap = 4, std::uint8_t background = 255);

/// Mean absolute difference of two same-sized images per channel value [0, 255].
double mean_abs_difference(const Image& a, const Image& b);

}  // namespace mg::viz
