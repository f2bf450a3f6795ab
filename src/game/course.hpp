#pragma once
/// A course: a round of holes, each on a field (docs/round.md "Course files").
///
/// Course files are YAML (`format_version: 1`); shipped ones live in data/courses/ and are named
/// without a path, like fields. A hole names a field (shipped name, or a path relative to the
/// course file) and may move its tee and hole:
///   name: my-course
///   max_strokes: 6
///   holes:
///     - {field: flat, tee: [0.2, -0.1], hole: [2.3, 0.3], par: 2}
///     - {field: path/to/field.yaml, par: 3}     # the field's own tee and hole
/// Validated once, on load: every field is loaded and checked with its tee and hole (a tee off the
/// lane or in an obstacle, a hole inside a block, a hole walled off from the tee (the round's
/// LaneRegion), par < 1, a key given twice, a name with a control character ... are one-line
/// errors naming the course file and the key).
#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "field/field.hpp"

namespace mg::game {

struct CourseHole {
  std::string field_name;  ///< as written in the course file
  field::Field field;      ///< loaded, with the hole's tee and hole applied; validated
  int par = 3;
};

struct Course {
  std::string name;
  std::string source;   ///< the file it was read from
  int max_strokes = 6;  ///< a hole ends after this many strokes, penalties included
  std::vector<CourseHole> holes;
};

/// Loads a course by shipped name (data/courses/NAME.yaml) or path. Throws InputError/IoError.
Course load_course(std::string_view name_or_path);
/// Parses course YAML text; fields named by a relative path are found from `base_dir`.
Course parse_course(std::string_view yaml_text, const std::string& source,
                    const std::filesystem::path& base_dir);
/// Names of the shipped courses, sorted.
std::vector<std::string> list_shipped_courses();

}  // namespace mg::game
