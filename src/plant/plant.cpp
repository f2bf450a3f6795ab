#include "plant/plant.hpp"

#include <cmath>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/rng.hpp"
#include "field/map_reader.hpp"
#include "plant/plant_reader.hpp"

namespace mg::plant {
namespace {

/// Plant files are a few hundred bytes; anything this large is not one.
constexpr std::size_t kMaxPlantBytes = 1 << 20;

void check_range(const std::string& source, const std::string& key, double v, double lo, double hi,
                 const char* unit) {
  if (!(v >= lo && v <= hi))
    throw InputError(
        fmt::format("{}: {}: expected {}..{}{}, got {}", source, key, lo, hi, unit, v));
}

/// A uniform draw in [lo, hi) from 53 random bits (the same on every platform).
double uniform(Rng& rng, double lo, double hi) {
  const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return lo + (hi - lo) * u;
}

}  // namespace

bool Plant::field_changed() const {
  return field.rolling_resistance || field.rolling_resistance_scale || field.sliding_friction ||
         field.sliding_friction_scale || field.extra_slope[0] != 0.0 ||
         field.extra_slope[1] != 0.0 || !field.bumps.empty();
}

bool Plant::arm_changed() const {
  bool friction = false;
  for (double f : arm.joint_friction) friction = friction || f != 0.0;
  return friction || arm.club_restitution_scale != 1.0;
}

bool Plant::empty() const {
  return !field_changed() && !arm_changed() &&
         field.hole_offset == std::array<double, 2>{0.0, 0.0} && arm.launch_angle_bias == 0.0 &&
         arm.club_speed_scale == 1.0 && arm.torque_noise == 0.0 && perception.noise == 0.0 &&
         perception.latency == 0.0;
}

void Plant::validate() const {
  const std::string s = source.empty() ? "plant" : source;
  const auto& f = field;
  if (f.rolling_resistance && f.rolling_resistance_scale)
    throw InputError(
        fmt::format("{}: field: rolling_resistance and rolling_resistance_scale: give one", s));
  if (f.sliding_friction && f.sliding_friction_scale)
    throw InputError(
        fmt::format("{}: field: sliding_friction and sliding_friction_scale: give one", s));
  if (f.rolling_resistance)
    check_range(s, "field.rolling_resistance", *f.rolling_resistance, 0.01, 1.0, "");
  if (f.rolling_resistance_scale)
    check_range(s, "field.rolling_resistance_scale", *f.rolling_resistance_scale, 0.2, 5.0, "");
  if (f.sliding_friction)
    check_range(s, "field.sliding_friction", *f.sliding_friction, 0.01, 2.0, "");
  if (f.sliding_friction_scale)
    check_range(s, "field.sliding_friction_scale", *f.sliding_friction_scale, 0.1, 5.0, "");
  for (int i = 0; i < 2; ++i) {
    check_range(s, fmt::format("field.extra_slope[{}]", i),
                f.extra_slope[static_cast<std::size_t>(i)], -0.1, 0.1, "");
    check_range(s, fmt::format("field.hole_offset[{}]", i),
                f.hole_offset[static_cast<std::size_t>(i)], -0.2, 0.2, " m");
  }
  if (f.bumps.size() > kMaxPlantBumps)
    throw InputError(fmt::format("{}: field.bumps: expected at most {} bumps, got {}", s,
                                 kMaxPlantBumps, f.bumps.size()));
  for (std::size_t i = 0; i < f.bumps.size(); ++i) {
    const auto& b = f.bumps[i];
    for (std::size_t k = 0; k < 2; ++k) {
      check_range(s, fmt::format("field.bumps[{}].center[{}]", i, k), b.center[k], -100.0, 100.0,
                  " m");
      check_range(s, fmt::format("field.bumps[{}].sigma[{}]", i, k), b.sigma[k], 0.02, 10.0, " m");
    }
    check_range(s, fmt::format("field.bumps[{}].height", i), b.height, -0.05, 0.05, " m");
  }
  check_range(s, "arm.launch_angle_bias", arm.launch_angle_bias, -0.1, 0.1, " rad");
  check_range(s, "arm.club_speed_scale", arm.club_speed_scale, 0.5, 1.5, "");
  check_range(s, "arm.club_restitution_scale", arm.club_restitution_scale, 0.5, 1.2, "");
  for (std::size_t j = 0; j < 7; ++j)
    check_range(s, fmt::format("arm.joint_friction[{}]", j), arm.joint_friction[j], 0.0, 20.0,
                " N m");
  check_range(s, "arm.torque_noise", arm.torque_noise, 0.0, 0.05, "");
  check_range(s, "perception.noise", perception.noise, 0.0, 0.05, " m");
  check_range(s, "perception.latency", perception.latency, 0.0, 0.5, " s");
}

void read_plant_sections(field::MapReader& r, Plant& p) {
  if (r.has("field")) {
    field::MapReader f = r.child("field");
    auto& t = p.field;
    if (f.has("rolling_resistance")) t.rolling_resistance = f.number("rolling_resistance");
    if (f.has("rolling_resistance_scale"))
      t.rolling_resistance_scale = f.number("rolling_resistance_scale");
    if (f.has("sliding_friction")) t.sliding_friction = f.number("sliding_friction");
    if (f.has("sliding_friction_scale"))
      t.sliding_friction_scale = f.number("sliding_friction_scale");
    t.extra_slope = f.numbers<2>("extra_slope", t.extra_slope);
    t.hole_offset = f.numbers<2>("hole_offset", t.hole_offset);
    if (f.has("bumps")) {
      const YAML::Node list = f.require("bumps");
      if (!list.IsSequence()) f.fail(f.full("bumps"), "expected a list of bumps");
      if (list.size() > kMaxPlantBumps)
        f.fail(f.full("bumps"), fmt::format("expected at most {} bumps", kMaxPlantBumps));
      for (std::size_t i = 0; i < list.size(); ++i) {
        field::MapReader b(list[i], f.source(), fmt::format("{}[{}]", f.full("bumps"), i));
        field::BumpTerm bump;
        bump.center = b.numbers<2>("center");
        bump.height = b.number("height");
        bump.sigma = b.numbers<2>("sigma");
        b.finish();
        t.bumps.push_back(bump);
      }
    }
    f.finish();
  }
  if (r.has("arm")) {
    field::MapReader a = r.child("arm");
    auto& t = p.arm;
    t.launch_angle_bias = a.number("launch_angle_bias", t.launch_angle_bias);
    t.club_speed_scale = a.number("club_speed_scale", t.club_speed_scale);
    t.club_restitution_scale = a.number("club_restitution_scale", t.club_restitution_scale);
    t.joint_friction = a.numbers<7>("joint_friction", t.joint_friction);
    t.torque_noise = a.number("torque_noise", t.torque_noise);
    a.finish();
  }
  if (r.has("perception")) {
    field::MapReader v = r.child("perception");
    p.perception.noise = v.number("noise", p.perception.noise);
    p.perception.latency = v.number("latency", p.perception.latency);
    v.finish();
  }
}

Plant parse_plant(std::string_view yaml_text, const std::string& source) {
  if (yaml_text.size() > kMaxPlantBytes)
    throw InputError(fmt::format("{}: {} bytes: a plant file is at most {} bytes", source,
                                 yaml_text.size(), kMaxPlantBytes));
  const YAML::Node root = field::load_yaml(yaml_text, source);
  Plant p;
  p.source = source;
  p.hash = content_hash(yaml_text);
  // Like fields and courses, a plant names its format: an empty file or one without the version
  // is not taken for the identity (a truncated or wrong file would play the robot's model).
  if (!root || root.IsNull())
    throw InputError(
        fmt::format("{}: empty plant file (expected format_version: {} and the keys that differ "
                    "from the robot's model)",
                    source, kPlantFormatVersion));
  try {
    field::MapReader r(root, source, "");
    const double version = r.number("format_version");
    if (version != kPlantFormatVersion)
      r.fail("format_version", fmt::format("expected {}, got {}", kPlantFormatVersion, version));
    read_plant_sections(r, p);
    r.finish();
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: malformed plant: {}", source, e.what()));
  }
  p.validate();
  return p;
}

std::string read_plant_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(
        fmt::format("plant: '{}': expected a plant file (YAML), {}", path.string(),
                    std::filesystem::exists(path, ec) ? "not a regular file" : "no such file"));
  if (std::filesystem::file_size(path, ec) > kMaxPlantBytes)
    throw InputError(fmt::format("plant: '{}': larger than {} bytes, not a plant file",
                                 path.string(), kMaxPlantBytes));
  return read_text_file(path);
}

Plant load_plant(const std::filesystem::path& path) {
  return parse_plant(read_plant_file(path), path.string());
}

double true_rolling_resistance(const field::Field& belief, const Plant& plant) {
  const auto& f = plant.field;
  if (f.rolling_resistance) return *f.rolling_resistance;
  if (f.rolling_resistance_scale) return belief.rolling_resistance * *f.rolling_resistance_scale;
  return belief.rolling_resistance;
}

double true_sliding_friction(const field::Field& belief, const Plant& plant) {
  const auto& f = plant.field;
  if (f.sliding_friction) return *f.sliding_friction;
  if (f.sliding_friction_scale) return belief.sliding_friction * *f.sliding_friction_scale;
  return belief.sliding_friction;
}

field::Field true_field(const field::Field& belief, const Plant& plant) {
  field::Field f = belief;
  if (!plant.field_changed()) return f;
  f.rolling_resistance = true_rolling_resistance(belief, plant);
  f.sliding_friction = true_sliding_friction(belief, plant);
  const auto& s = plant.field.extra_slope;
  if (s[0] != 0.0 || s[1] != 0.0) {
    field::PlaneTerm tilt;
    tilt.slope_x = s[0];
    tilt.slope_y = s[1];
    f.surface.terms.emplace_back(tilt);
  }
  for (const auto& bump : plant.field.bumps) f.surface.terms.emplace_back(bump);
  f.validate();
  return f;
}

Plant random_plant(std::uint64_t seed) {
  Rng rng(derive_seed(seed, 0x706c616e74ULL));  // "plant"
  Plant p;
  p.field.rolling_resistance_scale = uniform(rng, 0.8, 1.2);
  p.field.sliding_friction_scale = uniform(rng, 0.8, 1.2);
  p.field.extra_slope = {uniform(rng, -0.005, 0.005), uniform(rng, -0.005, 0.005)};
  p.field.hole_offset = {uniform(rng, -0.003, 0.003), uniform(rng, -0.003, 0.003)};
  p.arm.launch_angle_bias = uniform(rng, -0.005, 0.005);
  p.arm.club_speed_scale = uniform(rng, 0.95, 1.05);
  p.arm.club_restitution_scale = uniform(rng, 0.95, 1.05);
  // The wrist is light and the module has no friction compensation: joint 7 at 0.04 N m or more
  // keeps it from settling at the rest pose (stick-slip; docs/reality.md), so its range is small.
  constexpr std::array<double, 7> kFrictionMax{0.5, 0.5, 0.5, 0.5, 0.05, 0.05, 0.01};
  for (std::size_t j = 0; j < 7; ++j) p.arm.joint_friction[j] = uniform(rng, 0.0, kFrictionMax[j]);
  p.arm.torque_noise = uniform(rng, 0.0, 0.001);
  p.perception.noise = uniform(rng, 0.0, 0.001);
  p.perception.latency = uniform(rng, 0.0, 0.03);
  p.validate();
  return p;
}

std::string plant_to_yaml(const Plant& p) {
  const auto num = [](double v) { return fmt::format("{:.17g}", v); };
  std::string field, arm, perception;
  const auto& f = p.field;
  if (f.rolling_resistance) field += "  rolling_resistance: " + num(*f.rolling_resistance) + "\n";
  if (f.rolling_resistance_scale)
    field += "  rolling_resistance_scale: " + num(*f.rolling_resistance_scale) + "\n";
  if (f.sliding_friction) field += "  sliding_friction: " + num(*f.sliding_friction) + "\n";
  if (f.sliding_friction_scale)
    field += "  sliding_friction_scale: " + num(*f.sliding_friction_scale) + "\n";
  if (f.extra_slope[0] != 0.0 || f.extra_slope[1] != 0.0)
    field += fmt::format("  extra_slope: [{}, {}]\n", num(f.extra_slope[0]), num(f.extra_slope[1]));
  if (f.hole_offset[0] != 0.0 || f.hole_offset[1] != 0.0)
    field +=
        fmt::format("  hole_offset: [{}, {}]  # m\n", num(f.hole_offset[0]), num(f.hole_offset[1]));
  if (!f.bumps.empty()) {
    field += "  bumps:  # m\n";
    for (const auto& b : f.bumps)
      field +=
          fmt::format("    - {{center: [{}, {}], height: {}, sigma: [{}, {}]}}\n", num(b.center[0]),
                      num(b.center[1]), num(b.height), num(b.sigma[0]), num(b.sigma[1]));
  }
  const auto& a = p.arm;
  if (a.launch_angle_bias != 0.0)
    arm += "  launch_angle_bias: " + num(a.launch_angle_bias) + "  # rad\n";
  if (a.club_speed_scale != 1.0) arm += "  club_speed_scale: " + num(a.club_speed_scale) + "\n";
  if (a.club_restitution_scale != 1.0)
    arm += "  club_restitution_scale: " + num(a.club_restitution_scale) + "\n";
  bool friction = false;
  for (double v : a.joint_friction) friction = friction || v != 0.0;
  if (friction) {
    arm += "  joint_friction: [";
    for (std::size_t j = 0; j < 7; ++j) arm += (j ? ", " : "") + num(a.joint_friction[j]);
    arm += "]  # N m\n";
  }
  if (a.torque_noise != 0.0) arm += "  torque_noise: " + num(a.torque_noise) + "\n";
  if (p.perception.noise != 0.0) perception += "  noise: " + num(p.perception.noise) + "  # m\n";
  if (p.perception.latency != 0.0)
    perception += "  latency: " + num(p.perception.latency) + "  # s\n";
  std::string out =
      "# minigolf plant: the world as it really is (docs/reality.md)\nformat_version: 1\n";
  if (!field.empty()) out += "field:\n" + field;
  if (!arm.empty()) out += "arm:\n" + arm;
  if (!perception.empty()) out += "perception:\n" + perception;
  return out;
}

std::string content_hash(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return fmt::format("{:016x}", h);
}

}  // namespace mg::plant
