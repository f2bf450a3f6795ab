#include "game/course.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "field/map_reader.hpp"
#include "game/lane_region.hpp"

namespace mg::game {
namespace {

constexpr int kMaxHoles = 36;

/// A field name as a path relative to the course file; a shipped name stays a name.
std::string field_reference(const std::string& name, const std::filesystem::path& base_dir) {
  const bool is_path =
      name.find('/') != std::string::npos || name.ends_with(".yaml") || name.ends_with(".yml");
  if (!is_path) return name;
  const std::filesystem::path p(name);
  return p.is_absolute() ? name : (base_dir / p).string();
}

}  // namespace

Course parse_course(std::string_view yaml_text, const std::string& source,
                    const std::filesystem::path& base_dir) {
  const YAML::Node root = field::load_yaml(yaml_text, source);
  field::MapReader r(root, source, "");
  const int version = r.integer("format_version");
  if (version != 1)
    throw InputError(fmt::format("{}: format_version: expected 1, got {}", source, version));
  Course c;
  c.source = source;
  c.name = r.name("name", std::filesystem::path(source).stem().string());
  if (c.name.empty() || c.name.size() > 200)
    throw InputError(fmt::format("{}: name: expected 1..200 characters", source));
  c.max_strokes = r.has("max_strokes") ? r.integer("max_strokes") : c.max_strokes;
  if (c.max_strokes < 1 || c.max_strokes > 20)
    throw InputError(fmt::format("{}: max_strokes: expected 1..20, got {}", source, c.max_strokes));
  const YAML::Node holes = r.require("holes");
  if (!holes.IsSequence() || holes.size() == 0 || holes.size() > kMaxHoles)
    throw InputError(fmt::format("{}: holes: expected a list of 1..{} holes", source, kMaxHoles));
  for (std::size_t i = 0; i < holes.size(); ++i) {
    const std::string key = fmt::format("holes[{}]", i);
    field::MapReader h(holes[i], source, key);
    CourseHole hole;
    hole.field_name = h.text("field", "");
    if (hole.field_name.empty())
      throw InputError(fmt::format("{}: {}.field: missing (required)", source, key));
    hole.par = h.integer("par");
    if (hole.par < 1 || hole.par > 10)
      throw InputError(fmt::format("{}: {}.par: expected 1..10, got {}", source, key, hole.par));
    const bool has_tee = h.has("tee"), has_hole = h.has("hole");
    const auto tee = has_tee ? h.numbers<2>("tee") : std::array<double, 2>{};
    const auto cup = has_hole ? h.numbers<2>("hole") : std::array<double, 2>{};
    h.finish();
    try {
      hole.field = field::load_field(field_reference(hole.field_name, base_dir));
    } catch (const Error& e) {
      throw InputError(fmt::format("{}: {}.field: {}", source, key, e.what()));
    }
    if (has_tee) hole.field.tee = tee;
    if (has_hole) hole.field.hole.position = cup;
    try {
      hole.field.validate();
      if (std::hypot(hole.field.tee[0] - hole.field.hole.position[0],
                     hole.field.tee[1] - hole.field.hole.position[1]) <
          0.5 * hole.field.hole.diameter + hole.field.ball.radius)
        throw InputError("the tee lies in the hole");
      // The round's own flood fill: a hole walled off from the tee would be played as strokes
      // and penalties until max_strokes.
      if (!LaneRegion(hole.field, hole.field.hole.position).contains(hole.field.tee))
        throw InputError(fmt::format(
            "the hole ({}, {}) cannot be reached from the tee ({}, {}): no path on the lane "
            "between them clears the walls",
            hole.field.hole.position[0], hole.field.hole.position[1], hole.field.tee[0],
            hole.field.tee[1]));
    } catch (const InputError& e) {
      // The field's message names its own file and key: say which course entry set them.
      throw InputError(fmt::format("{}: {} (tee/hole): {}", source, key, e.what()));
    }
    c.holes.push_back(std::move(hole));
  }
  r.finish();
  return c;
}

Course load_course(std::string_view name_or_path) {
  const std::string arg(name_or_path);
  if (arg.empty()) throw InputError("course: expected a name or a path, got ''");
  const bool is_path =
      arg.find('/') != std::string::npos || arg.ends_with(".yaml") || arg.ends_with(".yml");
  std::filesystem::path path =
      is_path ? std::filesystem::path(arg) : data_dir() / "courses" / (arg + ".yaml");
  std::error_code ec;
  if (!is_path && !std::filesystem::exists(path, ec))
    throw InputError(
        fmt::format("course: unknown course '{}' (shipped: {}; give a path for "
                    "your own file)",
                    shown_path(arg), fmt::join(list_shipped_courses(), ", ")));
  return parse_course(read_text_file(path), path.string(), path.parent_path());
}

std::vector<std::string> list_shipped_courses() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(data_dir() / "courses", ec))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace mg::game
