#include "belief/belief.hpp"

#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "field/map_reader.hpp"
#include "plant/plant_reader.hpp"

namespace mg::belief {
namespace {

/// Belief files are plant files and a few more lines; anything this large is not one.
constexpr std::size_t kMaxBeliefBytes = 1 << 20;

/// yaml-cpp keeps both entries of a duplicated key and reads the first: a file that says a
/// value twice is an error here, anywhere in the tree.
void check_duplicates(const YAML::Node& node, const std::string& source, const std::string& path) {
  if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& kv : node) {
      const std::string key = kv.first.IsScalar() ? kv.first.as<std::string>() : "?";
      const std::string full = path.empty() ? key : path + "." + key;
      if (!seen.insert(key).second)
        throw InputError(fmt::format("{}: {}: duplicate key", source, full));
      check_duplicates(kv.second, source, full);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      check_duplicates(node[i], source, fmt::format("{}[{}]", path, i));
  }
}

void check_std(const std::string& source, const std::string& key, double v, double width) {
  if (!(std::isfinite(v) && v >= 0.0 && v <= width))
    throw InputError(fmt::format("{}: std.{}: expected a standard deviation in 0..{}, got {}",
                                 source, key, width, v));
}

/// Reads the `std` section: the plant's keys, each a standard deviation.
plant::Plant read_std(const YAML::Node& node, const std::string& source) {
  plant::Plant s = zero_plant();
  field::MapReader r(node, source, "std");
  plant::read_plant_sections(r, s);
  r.finish();
  // A bump is a shape put into the belief, not a number estimated with a spread.
  if (!s.field.bumps.empty())
    throw InputError(fmt::format("{}: std.field.bumps: bumps have no standard deviation", source));
  return s;
}

std::string num(double v) { return fmt::format("{:.17g}", v); }

/// The std plant's non-zero keys as the lines of a YAML section (indented by `indent`).
std::string std_to_yaml(const plant::Plant& s) {
  const auto& f = s.field;
  std::string field, arm, perception;
  const auto opt = [&](const char* key, const std::optional<double>& v) {
    if (v && *v != 0.0) field += fmt::format("    {}: {}\n", key, num(*v));
  };
  opt("rolling_resistance", f.rolling_resistance);
  opt("rolling_resistance_scale", f.rolling_resistance_scale);
  opt("sliding_friction", f.sliding_friction);
  opt("sliding_friction_scale", f.sliding_friction_scale);
  if (f.extra_slope[0] != 0.0 || f.extra_slope[1] != 0.0)
    field +=
        fmt::format("    extra_slope: [{}, {}]\n", num(f.extra_slope[0]), num(f.extra_slope[1]));
  if (f.hole_offset[0] != 0.0 || f.hole_offset[1] != 0.0)
    field += fmt::format("    hole_offset: [{}, {}]  # m\n", num(f.hole_offset[0]),
                         num(f.hole_offset[1]));
  const auto& a = s.arm;
  if (a.launch_angle_bias != 0.0)
    arm += "    launch_angle_bias: " + num(a.launch_angle_bias) + "  # rad\n";
  if (a.club_speed_scale != 0.0) arm += "    club_speed_scale: " + num(a.club_speed_scale) + "\n";
  if (a.club_restitution_scale != 0.0)
    arm += "    club_restitution_scale: " + num(a.club_restitution_scale) + "\n";
  bool friction = false;
  for (double v : a.joint_friction) friction = friction || v != 0.0;
  if (friction)
    arm += fmt::format("    joint_friction: [{}]  # N m\n", fmt::join(a.joint_friction, ", "));
  if (a.torque_noise != 0.0) arm += "    torque_noise: " + num(a.torque_noise) + "\n";
  if (s.perception.noise != 0.0) perception += "    noise: " + num(s.perception.noise) + "  # m\n";
  if (s.perception.latency != 0.0)
    perception += "    latency: " + num(s.perception.latency) + "  # s\n";
  std::string out;
  if (!field.empty()) out += "  field:\n" + field;
  if (!arm.empty()) out += "  arm:\n" + arm;
  if (!perception.empty()) out += "  perception:\n" + perception;
  return out;
}

/// The std of an absolute value given either directly or as a scale of `base`.
double absolute_std(const std::optional<double>& direct, const std::optional<double>& scale,
                    double base) {
  if (direct) return *direct;
  if (scale) return *scale * base;
  return 0.0;
}

}  // namespace

plant::Plant zero_plant() {
  plant::Plant p;
  p.arm.club_speed_scale = 0.0;
  p.arm.club_restitution_scale = 0.0;
  return p;
}

void validate_std(const plant::Plant& s, const std::string& source) {
  const auto& f = s.field;
  if (f.rolling_resistance)
    check_std(source, "field.rolling_resistance", *f.rolling_resistance, 1.0);
  if (f.rolling_resistance_scale)
    check_std(source, "field.rolling_resistance_scale", *f.rolling_resistance_scale, 5.0);
  if (f.sliding_friction) check_std(source, "field.sliding_friction", *f.sliding_friction, 2.0);
  if (f.sliding_friction_scale)
    check_std(source, "field.sliding_friction_scale", *f.sliding_friction_scale, 5.0);
  for (std::size_t i = 0; i < 2; ++i) {
    check_std(source, fmt::format("field.extra_slope[{}]", i), f.extra_slope[i], 0.2);
    check_std(source, fmt::format("field.hole_offset[{}]", i), f.hole_offset[i], 0.4);
  }
  check_std(source, "arm.launch_angle_bias", s.arm.launch_angle_bias, 0.2);
  check_std(source, "arm.club_speed_scale", s.arm.club_speed_scale, 1.0);
  check_std(source, "arm.club_restitution_scale", s.arm.club_restitution_scale, 0.7);
  for (std::size_t j = 0; j < 7; ++j)
    check_std(source, fmt::format("arm.joint_friction[{}]", j), s.arm.joint_friction[j], 20.0);
  check_std(source, "arm.torque_noise", s.arm.torque_noise, 0.05);
  check_std(source, "perception.noise", s.perception.noise, 0.05);
  check_std(source, "perception.latency", s.perception.latency, 0.5);
}

Belief parse_belief(std::string_view yaml_text, const std::string& source) {
  if (yaml_text.size() > kMaxBeliefBytes)
    throw InputError(fmt::format("{}: {} bytes: a belief file is at most {} bytes", source,
                                 yaml_text.size(), kMaxBeliefBytes));
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: malformed YAML: {}", source, e.what()));
  }
  Belief b;
  try {
    check_duplicates(root, source, "");
    if (root && !root.IsNull() && !root.IsMap())
      throw InputError(fmt::format("{}: the file: expected a mapping", source));
    std::string plant_text;
    if (root && root.IsMap()) {
      // The `std` and `putts` keys are the belief's; the rest is a plant file.
      const YAML::Node& map = root;  // const: a lookup never inserts
      YAML::Node rest = YAML::Clone(root);
      if (map["std"]) {
        b.std = read_std(map["std"], source);
        validate_std(b.std, source);
        rest.remove("std");
      }
      if (map["putts"]) {
        field::MapReader r(map, source, "");
        const double n = r.number("putts");
        if (n != std::floor(n) || n < 0 || n > kMaxBeliefPutts)
          r.fail("putts",
                 fmt::format("expected a whole number in 0..{}, got {}", kMaxBeliefPutts, n));
        b.putts = static_cast<int>(n);
        rest.remove("putts");
      }
      if (rest.size() > 0) {
        YAML::Emitter out;
        out << rest;
        plant_text = out.c_str();
      }
    }
    b.estimate = plant::parse_plant(plant_text, source);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: malformed belief: {}", source, e.what()));
  }
  b.estimate.hash = plant::content_hash(yaml_text);
  return b;
}

Belief load_belief(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(fmt::format(
        "belief: '{}': expected a belief file (YAML), {}", shown_path(path),
        std::filesystem::is_directory(path, ec)
            ? "got a directory"
            : (std::filesystem::exists(path, ec) ? "not a regular file" : "no such file")));
  if (std::filesystem::file_size(path, ec) > kMaxBeliefBytes)
    throw InputError(fmt::format("belief: '{}': larger than {} bytes, not a belief file",
                                 shown_path(path), kMaxBeliefBytes));
  return parse_belief(read_text_file(path, kMaxBeliefBytes), path.string());
}

std::string belief_to_yaml(const Belief& b) {
  std::string text = plant::plant_to_yaml(b.estimate);
  // plant_to_yaml's first line names a plant; this file is a belief.
  const auto eol = text.find('\n');
  text = "# minigolf belief: the robot's estimate of the world (docs/belief.md)" + text.substr(eol);
  const std::string s = std_to_yaml(b.std);
  if (!s.empty()) text += "std:\n" + s;
  text += fmt::format("putts: {}\n", b.putts);
  return text;
}

nlohmann::json belief_to_json(const Belief& b, const field::Field& field) {
  const plant::Plant& e = b.estimate;
  const plant::Plant& s = b.std;
  nlohmann::json j;
  j["field"] = {
      {"rolling_resistance", plant::true_rolling_resistance(field, e)},
      {"extra_slope", {e.field.extra_slope[0], e.field.extra_slope[1]}},
      {"hole_offset", {e.field.hole_offset[0], e.field.hole_offset[1]}},
      {"sliding_friction", plant::true_sliding_friction(field, e)},
  };
  if (!e.field.bumps.empty()) {
    nlohmann::json bumps = nlohmann::json::array();
    for (const auto& bump : e.field.bumps)
      bumps.push_back({{"center", bump.center}, {"height", bump.height}, {"sigma", bump.sigma}});
    j["field"]["bumps"] = bumps;
  }
  j["arm"] = {{"launch_angle_bias", e.arm.launch_angle_bias},
              {"club_speed_scale", e.arm.club_speed_scale}};
  j["std"] = {
      {"field",
       {{"rolling_resistance",
         absolute_std(s.field.rolling_resistance, s.field.rolling_resistance_scale,
                      field.rolling_resistance)},
        {"extra_slope", {s.field.extra_slope[0], s.field.extra_slope[1]}},
        {"hole_offset", {s.field.hole_offset[0], s.field.hole_offset[1]}},
        {"sliding_friction", absolute_std(s.field.sliding_friction, s.field.sliding_friction_scale,
                                          field.sliding_friction)}}},
      {"arm",
       {{"launch_angle_bias", s.arm.launch_angle_bias},
        {"club_speed_scale", s.arm.club_speed_scale}}},
  };
  j["putts"] = b.putts;
  return j;
}

field::Field believed_field(const field::Field& surveyed, const Belief& belief) {
  return plant::true_field(surveyed, belief.estimate);
}

}  // namespace mg::belief
