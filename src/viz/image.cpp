#include "viz/image.hpp"

#include <png.h>

#include <cstdlib>
#include <cstring>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"

namespace mg::viz {

std::string encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0) throw InputError("png: empty image");
  png_image p{};
  p.version = PNG_IMAGE_VERSION;
  p.width = static_cast<png_uint_32>(image.width);
  p.height = static_cast<png_uint_32>(image.height);
  p.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&p, nullptr, &size, 0, image.rgb.data(), 0, nullptr))
    throw Error(fmt::format("png: cannot encode: {}", p.message));
  std::string out(size, '\0');
  if (!png_image_write_to_memory(&p, out.data(), &size, 0, image.rgb.data(), 0, nullptr))
    throw Error(fmt::format("png: cannot encode: {}", p.message));
  out.resize(size);
  return out;
}

void write_png(const std::filesystem::path& path, const Image& image) {
  write_file_atomic(path, encode_png(image));
}

Image read_png(const std::filesystem::path& path) {
  check_input_file(path);
  png_image p{};
  p.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&p, path.c_str()))
    throw IoError(fmt::format("{}: cannot read PNG: {}", path.string(), p.message));
  p.format = PNG_FORMAT_RGB;
  Image image(static_cast<int>(p.width), static_cast<int>(p.height));
  if (!png_image_finish_read(&p, nullptr, image.rgb.data(), 0, nullptr)) {
    png_image_free(&p);
    throw IoError(fmt::format("{}: cannot read PNG: {}", path.string(), p.message));
  }
  return image;
}

Image filmstrip(const std::vector<Image>& frames, int gap, std::uint8_t background) {
  if (frames.empty()) throw InputError("filmstrip: no frames");
  const int w = frames.front().width, h = frames.front().height;
  for (const auto& f : frames)
    if (f.width != w || f.height != h) throw InputError("filmstrip: frames of different sizes");
  const int n = static_cast<int>(frames.size());
  Image out(n * w + (n - 1) * gap, h);
  std::memset(out.rgb.data(), background, out.rgb.size());
  for (int k = 0; k < n; ++k)
    for (int y = 0; y < h; ++y)
      std::memcpy(out.pixel(k * (w + gap), y), frames[static_cast<std::size_t>(k)].pixel(0, y),
                  static_cast<std::size_t>(w) * 3);
  return out;
}

double mean_abs_difference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw InputError("image difference: different sizes");
  double sum = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) sum += std::abs(int(a.rgb[i]) - int(b.rgb[i]));
  return a.rgb.empty() ? 0.0 : sum / static_cast<double>(a.rgb.size());
}

}  // namespace mg::viz
