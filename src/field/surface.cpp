#include "field/surface.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <png.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"

namespace mg::field {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct HeightVisitor {
  double x, y;
  double operator()(const PlaneTerm& t) const { return t.offset + t.slope_x * x + t.slope_y * y; }
  double operator()(const BumpTerm& t) const {
    const double u = (x - t.center[0]) / t.sigma[0], w = (y - t.center[1]) / t.sigma[1];
    return t.height * std::exp(-0.5 * (u * u + w * w));
  }
  double operator()(const HillTerm& t) const {
    const double u = (x - t.crest[0]) * t.direction[0] + (y - t.crest[1]) * t.direction[1];
    if (std::abs(u) >= t.half_width) return 0.0;
    return t.height * 0.5 * (1.0 + std::cos(kPi * u / t.half_width));
  }
  double operator()(const ArctanTerm& t) const {
    const double fy = t.scale_y == 0.0 ? 1.0 : std::atan(t.scale_y * (y - t.center[1]));
    return t.amplitude * std::atan(t.scale_x * (x - t.center[0])) * fy;
  }
  double operator()(const HeightmapTerm& t) const {
    double gx, gy;
    grid_coords(t, gx, gy);
    const int c0 = std::clamp(static_cast<int>(std::floor(gx)), 0, t.cols - 2);
    const int r0 = std::clamp(static_cast<int>(std::floor(gy)), 0, t.rows - 2);
    const double fx = std::clamp(gx - c0, 0.0, 1.0), fy = std::clamp(gy - r0, 0.0, 1.0);
    const auto h = [&](int r, int c) {
      return t.heights[static_cast<std::size_t>(r * t.cols + c)];
    };
    return (1 - fy) * ((1 - fx) * h(r0, c0) + fx * h(r0, c0 + 1)) +
           fy * ((1 - fx) * h(r0 + 1, c0) + fx * h(r0 + 1, c0 + 1));
  }
  double operator()(const FlattenTerm&) const { return 0.0; }  // handled by Surface
  void grid_coords(const HeightmapTerm& t, double& gx, double& gy) const {
    gx = (x - t.bounds[0]) / (t.bounds[1] - t.bounds[0]) * (t.cols - 1);
    gy = (y - t.bounds[2]) / (t.bounds[3] - t.bounds[2]) * (t.rows - 1);
  }
};

struct GradientVisitor {
  double x, y;
  std::array<double, 2> operator()(const PlaneTerm& t) const { return {t.slope_x, t.slope_y}; }
  std::array<double, 2> operator()(const BumpTerm& t) const {
    const double z = HeightVisitor{x, y}(t);
    return {-z * (x - t.center[0]) / (t.sigma[0] * t.sigma[0]),
            -z * (y - t.center[1]) / (t.sigma[1] * t.sigma[1])};
  }
  std::array<double, 2> operator()(const HillTerm& t) const {
    const double u = (x - t.crest[0]) * t.direction[0] + (y - t.crest[1]) * t.direction[1];
    if (std::abs(u) >= t.half_width) return {0.0, 0.0};
    const double dz_du = -t.height * 0.5 * kPi / t.half_width * std::sin(kPi * u / t.half_width);
    return {dz_du * t.direction[0], dz_du * t.direction[1]};
  }
  std::array<double, 2> operator()(const ArctanTerm& t) const {
    const double ax = t.scale_x * (x - t.center[0]);
    const double dfx = t.amplitude * t.scale_x / (1.0 + ax * ax);
    if (t.scale_y == 0.0) return {dfx, 0.0};
    const double ay = t.scale_y * (y - t.center[1]);
    return {dfx * std::atan(ay), t.amplitude * std::atan(ax) * t.scale_y / (1.0 + ay * ay)};
  }
  std::array<double, 2> operator()(const HeightmapTerm& t) const {
    // Central differences of the bilinear interpolant, half a cell wide.
    const double hx = 0.5 * (t.bounds[1] - t.bounds[0]) / (t.cols - 1);
    const double hy = 0.5 * (t.bounds[3] - t.bounds[2]) / (t.rows - 1);
    return {(HeightVisitor{x + hx, y}(t)-HeightVisitor{x - hx, y}(t)) / (2 * hx),
            (HeightVisitor{x, y + hy}(t)-HeightVisitor{x, y - hy}(t)) / (2 * hy)};
  }
  std::array<double, 2> operator()(const FlattenTerm&) const { return {0.0, 0.0}; }
};

HeightmapTerm load_png_heightmap(const std::string& path, double z_min, double z_max) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw InputError(fmt::format("{}: not a readable PNG image ({})", path, image.message));
  image.format = PNG_FORMAT_GRAY;  // 8-bit grey; colour images are converted
  std::vector<png_byte> pixels(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr)) {
    png_image_free(&image);
    throw InputError(fmt::format("{}: cannot decode PNG image ({})", path, image.message));
  }
  HeightmapTerm t;
  t.rows = static_cast<int>(image.height);
  t.cols = static_cast<int>(image.width);
  t.heights.resize(pixels.size());
  // Image row 0 is the top of the picture: the far side (y_max) of the lane.
  for (int r = 0; r < t.rows; ++r)
    for (int c = 0; c < t.cols; ++c)
      t.heights[static_cast<std::size_t>(r * t.cols + c)] =
          z_min +
          (z_max - z_min) * pixels[static_cast<std::size_t>((t.rows - 1 - r) * t.cols + c)] / 255.0;
  return t;
}

HeightmapTerm load_csv_heightmap(const std::string& path) {
  // A headerless grid: parse with a synthetic header so CsvTable does the number checking.
  const std::string text = read_text_file(path);
  const auto first_newline = text.find('\n');
  const std::string first_line = text.substr(0, first_newline);
  const auto cols = static_cast<int>(std::count(first_line.begin(), first_line.end(), ',') + 1);
  std::string header;
  for (int c = 0; c < cols; ++c) header += (c ? ",c" : "c") + std::to_string(c);
  const CsvTable table = parse_csv(header + "\n" + text, path);
  HeightmapTerm t;
  t.rows = static_cast<int>(table.num_rows());
  t.cols = cols;
  for (const auto& row : table.rows) t.heights.insert(t.heights.end(), row.begin(), row.end());
  return t;
}

}  // namespace

void pad_weight(const FlattenTerm& t, double r, double& w, double& dw_dr) {
  if (r <= t.radius) {
    w = 1.0, dw_dr = 0.0;
  } else if (r >= t.blend_radius) {
    w = 0.0, dw_dr = 0.0;
  } else {
    const double width = t.blend_radius - t.radius, s = (r - t.radius) / width;
    w = 1.0 - s * s * (3.0 - 2.0 * s);
    dw_dr = -6.0 * s * (1.0 - s) / width;
  }
}

double Surface::partial_height(std::size_t n, double x, double y) const {
  double z = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (const auto* pad = std::get_if<FlattenTerm>(&terms[i])) {
      const double r = std::hypot(x - pad->center[0], y - pad->center[1]);
      if (r >= pad->blend_radius) continue;
      double w, dw_dr;
      pad_weight(*pad, r, w, dw_dr);
      z += w * (partial_height(i, pad->center[0], pad->center[1]) - z);
    } else {
      z += std::visit(HeightVisitor{x, y}, terms[i]);
    }
  }
  return z;
}

void Surface::evaluate(std::size_t n, double x, double y, double& z,
                       std::array<double, 2>& g) const {
  z = 0.0;
  g = {0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    if (const auto* pad = std::get_if<FlattenTerm>(&terms[i])) {
      const double dx = x - pad->center[0], dy = y - pad->center[1], r = std::hypot(dx, dy);
      if (r >= pad->blend_radius) continue;
      double w, dw_dr;
      pad_weight(*pad, r, w, dw_dr);
      const double dz = partial_height(i, pad->center[0], pad->center[1]) - z;
      // grad(z + w dz) = (1 - w) grad z + dz grad w, grad w = w'(r) (dx, dy) / r.
      const double k = r > 0.0 ? dw_dr / r : 0.0;
      g = {(1.0 - w) * g[0] + dz * k * dx, (1.0 - w) * g[1] + dz * k * dy};
      z += w * dz;
    } else {
      z += std::visit(HeightVisitor{x, y}, terms[i]);
      const auto gt = std::visit(GradientVisitor{x, y}, terms[i]);
      g[0] += gt[0];
      g[1] += gt[1];
    }
  }
}

double Surface::height(double x, double y) const { return partial_height(terms.size(), x, y); }

std::array<double, 2> Surface::gradient(double x, double y) const {
  double z;
  std::array<double, 2> g;
  evaluate(terms.size(), x, y, z, g);
  return g;
}

HeightmapTerm load_heightmap(const std::string& path, std::array<double, 4> bounds, double z_min,
                             double z_max) {
  check_input_file(path);  // a regular, bounded file: libpng would block on a FIFO
  const std::string ext = std::filesystem::path(path).extension().string();
  HeightmapTerm t;
  if (ext == ".png" || ext == ".PNG") {
    t = load_png_heightmap(path, z_min, z_max);
  } else if (ext == ".csv") {
    t = load_csv_heightmap(path);
  } else {
    throw InputError(fmt::format("{}: heightmap must be .png or .csv, got '{}'", path, ext));
  }
  if (t.rows < 2 || t.cols < 2)
    throw InputError(
        fmt::format("{}: heightmap needs at least 2x2 values, got {}x{}", path, t.rows, t.cols));
  t.source = path;
  t.bounds = bounds;
  return t;
}

}  // namespace mg::field
