#include "vision/rig.hpp"

#include <cmath>
#include <set>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "field/map_reader.hpp"
#include "vision/camera_model.hpp"

namespace mg::vision {
namespace {

constexpr std::size_t kMaxRigBytes = 1 << 20;

void check_range(const field::MapReader& r, const std::string& key, double v, double lo, double hi,
                 const char* unit) {
  if (!(v >= lo && v <= hi))
    r.fail(r.full(key), fmt::format("expected {}..{}{}, got {}", lo, hi, unit, v));
}

CameraSpec read_camera(field::MapReader& r) {
  CameraSpec c;
  c.name = r.name("name", "");
  if (c.name.empty()) r.fail(r.full("name"), "missing (required): a non-empty name");
  c.position = r.numbers<3>("position");
  c.look_at = r.numbers<3>("look_at");
  c.up = r.numbers<3>("up", c.up);
  c.fovy_deg = r.number("fovy_deg");
  c.width = r.integer("width");
  c.height = r.integer("height");
  c.rate_hz = r.number("rate_hz");
  c.latency = r.number("latency", c.latency);
  if (r.has("distortion")) {
    field::MapReader d = r.child("distortion");
    c.distortion.k1 = d.number("k1", 0.0);
    c.distortion.k2 = d.number("k2", 0.0);
    c.distortion.p1 = d.number("p1", 0.0);
    c.distortion.p2 = d.number("p2", 0.0);
    c.distortion.k3 = d.number("k3", 0.0);
    d.finish();
    check_range(d, "k1", c.distortion.k1, -0.5, 0.5, "");
    check_range(d, "k2", c.distortion.k2, -0.5, 0.5, "");
    check_range(d, "p1", c.distortion.p1, -0.05, 0.05, "");
    check_range(d, "p2", c.distortion.p2, -0.05, 0.05, "");
    check_range(d, "k3", c.distortion.k3, -0.5, 0.5, "");
  }
  r.finish();
  for (int i = 0; i < 3; ++i) {
    const auto k = static_cast<std::size_t>(i);
    check_range(r, fmt::format("position[{}]", i), c.position[k], -20.0, 20.0, " m");
    check_range(r, fmt::format("look_at[{}]", i), c.look_at[k], -20.0, 20.0, " m");
    check_range(r, fmt::format("up[{}]", i), c.up[k], -1e3, 1e3, "");
  }
  check_range(r, "fovy_deg", c.fovy_deg, 10.0, 120.0, " deg");
  check_range(r, "width", c.width, 16, 4096, " pixels");
  check_range(r, "height", c.height, 16, 4096, " pixels");
  check_range(r, "rate_hz", c.rate_hz, 1.0, 1000.0, " Hz");
  check_range(r, "latency", c.latency, 0.0, 1.0, " s");
  const Eigen::Vector3d pos(c.position.data()), at(c.look_at.data()), up(c.up.data());
  const double dist = (at - pos).norm();
  if (!(dist >= 0.1))
    r.fail(r.full("look_at"), fmt::format("expected a point at least 0.1 m from position, got "
                                          "one {:.3g} m away",
                                          dist));
  if (!(up.norm() > 1e-9) || (at - pos).normalized().cross(up.normalized()).norm() < 0.05)
    r.fail(r.full("up"),
           "expected a direction at least 3 degrees off the viewing direction (position to "
           "look_at), got one along it");
  return c;
}

}  // namespace

Rig parse_rig(std::string_view yaml_text, const std::string& source) {
  if (yaml_text.size() > kMaxRigBytes)
    throw InputError(fmt::format("{}: {} bytes: a rig file is at most {} bytes", source,
                                 yaml_text.size(), kMaxRigBytes));
  const YAML::Node root = field::load_yaml(yaml_text, source);
  if (!root || root.IsNull())
    throw InputError(fmt::format("{}: empty rig file (expected format_version: {}, name, cameras)",
                                 source, kRigFormatVersion));
  Rig rig;
  rig.source = source;
  try {
    field::MapReader r(root, source, "");
    const double version = r.number("format_version");
    if (version != kRigFormatVersion)
      r.fail("format_version", fmt::format("expected {}, got {}", kRigFormatVersion, version));
    rig.name = r.name("name", "");
    if (rig.name.empty()) r.fail("name", "missing (required): a non-empty name");
    const YAML::Node cams = r.require("cameras");
    if (!cams.IsSequence() || cams.size() < 2 || cams.size() > 8)
      r.fail("cameras", fmt::format("expected a list of 2..8 cameras, got {}",
                                    cams.IsSequence() ? std::to_string(cams.size()) + " cameras"
                                                      : std::string("no list")));
    r.finish();
    std::set<std::string> names;
    for (std::size_t i = 0; i < cams.size(); ++i) {
      field::MapReader c(cams[i], source, fmt::format("cameras[{}]", i));
      rig.cameras.push_back(read_camera(c));
      if (!names.insert(rig.cameras.back().name).second)
        c.fail(c.full("name"), fmt::format("'{}' is used twice (expected one name per camera)",
                                           rig.cameras.back().name));
    }
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: malformed rig: {}", source, e.what()));
  }
  return rig;
}

Rig load_rig(const std::string& name_or_path) {
  std::filesystem::path path(name_or_path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec) && path.extension().empty() &&
      name_or_path.find('/') == std::string::npos)
    path = data_dir() / "rigs" / (name_or_path + ".yaml");
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(
        fmt::format("rig: '{}': expected a rig file (YAML) or a shipped rig name, {}", name_or_path,
                    std::filesystem::exists(path, ec) ? "not a regular file" : "no such file"));
  if (std::filesystem::file_size(path, ec) > kMaxRigBytes)
    throw InputError(fmt::format("rig: '{}': larger than {} bytes, not a rig file", path.string(),
                                 kMaxRigBytes));
  return parse_rig(read_text_file(path), path.string());
}

Rig bump_camera(Rig rig, const std::string& name, const std::array<double, 3>& offset,
                double yaw_deg, double pitch_deg) {
  const Eigen::Vector3d d(offset.data());
  if (!(d.norm() <= 0.1) || !(std::abs(yaw_deg) <= 10.0) || !(std::abs(pitch_deg) <= 10.0))
    throw InputError(fmt::format(
        "bump: expected a move of at most 0.1 m and turns of at most 10 degrees, got {:.3g} m, "
        "{:.3g} and {:.3g} degrees",
        d.norm(), yaw_deg, pitch_deg));
  for (auto& c : rig.cameras) {
    if (c.name != name) continue;
    constexpr double kDeg = 3.14159265358979323846 / 180.0;
    const Eigen::Vector3d pos(c.position.data()), at(c.look_at.data());
    Eigen::Vector3d dir = at - pos;
    const Eigen::Vector3d right = dir.cross(Eigen::Vector3d(c.up.data())).normalized();
    dir = Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
          (Eigen::AngleAxisd(pitch_deg * kDeg, right) * dir);
    for (int k = 0; k < 3; ++k) {
      c.position[static_cast<std::size_t>(k)] = pos[k] + d[k];
      c.look_at[static_cast<std::size_t>(k)] = pos[k] + d[k] + dir[k];
    }
    return rig;
  }
  throw InputError(fmt::format("bump: no camera '{}' in rig '{}'", name, rig.name));
}

void check_rig_sees_field(const Rig& rig, const field::Field& field) {
  const auto& b = field.bounds;
  constexpr int kGrid = 25;
  for (std::size_t i = 0; i < rig.cameras.size(); ++i) {
    const CameraModel cam = camera_from_spec(rig.cameras[i]);
    int seen = 0;
    for (int ix = 0; ix <= kGrid; ++ix)
      for (int iy = 0; iy <= kGrid; ++iy) {
        const double x = b[0] + (b[1] - b[0]) * ix / kGrid, y = b[2] + (b[3] - b[2]) * iy / kGrid;
        const auto px = project(cam, {x, y, field.height(x, y)});
        if (px && in_image(cam, *px)) ++seen;
      }
    if (seen == 0)
      throw InputError(fmt::format(
          "{}: cameras[{}]: camera '{}' sees no part of the lane of field '{}' (look_at, "
          "position, fovy_deg)",
          rig.source, i, rig.cameras[i].name, field.name));
  }
}

}  // namespace mg::vision
