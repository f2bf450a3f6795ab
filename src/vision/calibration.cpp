#include "vision/calibration.hpp"

#include <cmath>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "field/map_reader.hpp"

namespace mg::vision {
namespace {

constexpr std::size_t kMaxBytes = 1 << 20;

void check_range(const field::MapReader& r, const std::string& key, double v, double lo,
                 double hi) {
  if (!(v >= lo && v <= hi)) r.fail(r.full(key), fmt::format("expected {}..{}, got {}", lo, hi, v));
}

}  // namespace

Calibration exact_calibration(const Rig& rig) {
  Calibration c;
  c.rig = rig.name;
  for (const auto& s : rig.cameras) {
    c.cameras.push_back(camera_from_spec(s));
    c.rms_px.push_back(0.0);
  }
  c.source = "exact (" + rig.source + ")";
  return c;
}

std::string format_calibration(const Calibration& c) {
  std::string out = fmt::format(
      "# Written by `minigolf vision calibrate`: the robot's belief of its cameras.\n"
      "format_version: {}\nrig: {}\nviews: {}\nstereo_rms_px: {}\ncameras:\n",
      kCalibrationFormatVersion, c.rig, c.views, format_exact(c.stereo_rms_px));
  for (std::size_t i = 0; i < c.cameras.size(); ++i) {
    const CameraModel& m = c.cameras[i];
    std::vector<std::string> rot, tr, d;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) rot.push_back(format_exact(m.R(r, k)));
    for (int k = 0; k < 3; ++k) tr.push_back(format_exact(m.t[k]));
    out += fmt::format(
        "  - name: {}\n    width: {}\n    height: {}\n    fx: {}\n    fy: {}\n    cx: {}\n"
        "    cy: {}\n    distortion: {{k1: {}, k2: {}, p1: {}, p2: {}, k3: {}}}\n"
        "    rotation: [{}]\n    translation: [{}]\n    rate_hz: {}\n    latency: {}\n"
        "    rms_px: {}\n",
        m.name, m.width, m.height, format_exact(m.fx), format_exact(m.fy), format_exact(m.cx),
        format_exact(m.cy), format_exact(m.dist[0]), format_exact(m.dist[1]),
        format_exact(m.dist[2]), format_exact(m.dist[3]), format_exact(m.dist[4]),
        fmt::join(rot, ", "), fmt::join(tr, ", "), format_exact(m.rate_hz), format_exact(m.latency),
        format_exact(i < c.rms_px.size() ? c.rms_px[i] : 0.0));
  }
  return out;
}

Calibration parse_calibration(std::string_view text, const std::string& source) {
  if (text.size() > kMaxBytes)
    throw InputError(fmt::format("{}: larger than {} bytes, not a calibration", source, kMaxBytes));
  const YAML::Node root = field::load_yaml(text, source);
  if (!root || root.IsNull()) throw InputError(fmt::format("{}: empty calibration file", source));
  Calibration c;
  c.source = source;
  try {
    field::MapReader r(root, source, "");
    const double version = r.number("format_version");
    if (version != kCalibrationFormatVersion)
      r.fail("format_version",
             fmt::format("expected {}, got {}", kCalibrationFormatVersion, version));
    c.rig = r.name("rig", "");
    c.views = r.integer("views");
    c.stereo_rms_px = r.number("stereo_rms_px");
    check_range(r, "stereo_rms_px", c.stereo_rms_px, 0.0, 100.0);
    const YAML::Node cams = r.require("cameras");
    if (!cams.IsSequence() || cams.size() < 2 || cams.size() > 8)
      r.fail("cameras", "expected a list of 2..8 cameras");
    r.finish();
    for (std::size_t i = 0; i < cams.size(); ++i) {
      field::MapReader m(cams[i], source, fmt::format("cameras[{}]", i));
      CameraModel cam;
      cam.name = m.name("name", "");
      cam.width = m.integer("width");
      cam.height = m.integer("height");
      check_range(m, "width", cam.width, 16, 4096);
      check_range(m, "height", cam.height, 16, 4096);
      cam.fx = m.number("fx");
      cam.fy = m.number("fy");
      cam.cx = m.number("cx");
      cam.cy = m.number("cy");
      check_range(m, "fx", cam.fx, 1.0, 1e5);
      check_range(m, "fy", cam.fy, 1.0, 1e5);
      check_range(m, "cx", cam.cx, -0.5, cam.width - 0.5);
      check_range(m, "cy", cam.cy, -0.5, cam.height - 0.5);
      {
        field::MapReader d = m.child("distortion");
        const char* keys[] = {"k1", "k2", "p1", "p2", "k3"};
        for (std::size_t k = 0; k < 5; ++k) {
          cam.dist[k] = d.number(keys[k]);
          check_range(d, keys[k], cam.dist[k], -10.0, 10.0);
        }
        d.finish();
      }
      const auto rot = m.numbers<9>("rotation");
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) cam.R(a, b) = rot[static_cast<std::size_t>(3 * a + b)];
      const double ortho = (cam.R * cam.R.transpose() - Eigen::Matrix3d::Identity()).norm();
      if (!(ortho < 1e-6) || !(cam.R.determinant() > 0))
        m.fail(
            m.full("rotation"),
            fmt::format("expected a rotation matrix (orthonormal, det +1), off by {:.3g}", ortho));
      const auto tr = m.numbers<3>("translation");
      cam.t = Eigen::Vector3d(tr[0], tr[1], tr[2]);
      check_range(m, "translation", cam.t.norm(), 0.0, 100.0);
      cam.rate_hz = m.number("rate_hz");
      check_range(m, "rate_hz", cam.rate_hz, 1.0, 1000.0);
      cam.latency = m.number("latency");
      check_range(m, "latency", cam.latency, 0.0, 1.0);
      const double rms = m.number("rms_px");
      check_range(m, "rms_px", rms, 0.0, 100.0);
      m.finish();
      c.cameras.push_back(cam);
      c.rms_px.push_back(rms);
    }
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: malformed calibration: {}", source, e.what()));
  }
  return c;
}

Calibration load_calibration(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(
        fmt::format("calibration: '{}': expected a calibration file, {}", path,
                    std::filesystem::exists(path, ec) ? "not a regular file" : "no such file"));
  return parse_calibration(read_text_file(path), path);
}

void check_calibration_matches(const Calibration& c, const Rig& rig) {
  if (c.cameras.size() != rig.cameras.size())
    throw InputError(fmt::format("{}: cameras: {} cameras, but rig '{}' has {}", c.source,
                                 c.cameras.size(), rig.name, rig.cameras.size()));
  for (std::size_t i = 0; i < c.cameras.size(); ++i) {
    const auto& a = c.cameras[i];
    const auto& b = rig.cameras[i];
    if (a.name != b.name || a.width != b.width || a.height != b.height)
      throw InputError(fmt::format(
          "{}: cameras[{}]: '{}' {}x{} does not match rig camera '{}' {}x{} ({})", c.source, i,
          a.name, a.width, a.height, b.name, b.width, b.height, rig.source));
  }
}

}  // namespace mg::vision
