// Course files: the shipped courses load; every bad key is a one-line error naming file and key.
#include "game/course.hpp"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg::game {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    parse_course(yaml, "c.yaml", ".");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Course, ShippedCoursesLoadWithTheirFieldsAndHoles) {
  const auto names = list_shipped_courses();
  ASSERT_GE(names.size(), 3u);
  int holes = 0;
  for (const auto& n : names) {
    const Course c = load_course(n);
    EXPECT_FALSE(c.holes.empty()) << n;
    for (const auto& h : c.holes) {
      EXPECT_GE(h.par, 1) << n;
      EXPECT_NO_THROW(h.field.validate()) << n;
    }
    holes += static_cast<int>(c.holes.size());
  }
  EXPECT_GE(holes, 9);
}

TEST(Course, TeeAndHoleOverrideTheFieldsOwn) {
  const Course c = parse_course(R"(format_version: 1
name: two
max_strokes: 5
holes:
  - {field: flat, tee: [0.2, -0.1], hole: [2.3, 0.3], par: 2}
  - {field: flat, par: 3}
)",
                                "c.yaml", ".");
  EXPECT_EQ(c.name, "two");
  EXPECT_EQ(c.max_strokes, 5);
  ASSERT_EQ(c.holes.size(), 2u);
  EXPECT_EQ(c.holes[0].field.tee[0], 0.2);
  EXPECT_EQ(c.holes[0].field.hole.position[1], 0.3);
  EXPECT_EQ(c.holes[1].par, 3);
  EXPECT_EQ(c.holes[1].field.tee, field::load_field("flat").tee);
}

TEST(Course, FieldPathsAreRelativeToTheCourseFile) {
  const auto dir = std::filesystem::temp_directory_path() / "mg_course_rel";
  std::filesystem::create_directories(dir / "sub");
  std::filesystem::copy_file(
      std::filesystem::path(MINIGOLF_TEST_DATA_DIR) / ".." / ".." / "data" / "fields" / "flat.yaml",
      dir / "sub" / "mine.yaml", std::filesystem::copy_options::overwrite_existing);
  {
    std::ofstream f(dir / "course.yaml");
    f << "format_version: 1\nname: rel\nholes:\n  - {field: sub/mine.yaml, par: 2}\n";
  }
  const Course c = load_course((dir / "course.yaml").string());
  ASSERT_EQ(c.holes.size(), 1u);
  EXPECT_EQ(c.holes[0].field_name, "sub/mine.yaml");
  std::filesystem::remove_all(dir);
}

TEST(Course, BadFilesAreOneLineErrorsNamingFileAndKey) {
  const std::string head = "format_version: 1\nname: x\nholes:\n";
  struct Case {
    std::string yaml, expected;
  };
  const Case cases[] = {
      {"name: x\nholes: []\n", "format_version"},
      {"format_version: 2\nname: x\nholes: [{field: flat, par: 2}]\n", "format_version"},
      {"format_version: 1\nname: x\nholes: []\n", "holes"},
      {head + "  - {field: flat, par: 0}\n", "holes[0].par"},
      {head + "  - {field: flat}\n", "holes[0].par"},
      {head + "  - {par: 2}\n", "holes[0].field"},
      {head + "  - {field: no-such-field, par: 2}\n", "holes[0].field"},
      {head + "  - {field: flat, tee: [9.0, 0.0], par: 2}\n", "holes[0]"},
      {head + "  - {field: flat, tee: [0.0, .nan], par: 2}\n", "holes[0]"},
      {head + "  - {field: flat, hole: [1.5, 0.0], tee: [1.5, 0.01], par: 2}\n", "tee"},
      {head + "  - {field: bank-shot, hole: [1.0, 0.0], par: 2}\n", "holes[0]"},
      {head + "  - {field: bank-shot, tee: [1.0, 0.1], par: 2}\n", "holes[0]"},
      {head + "  - {field: flat, par: 2, colour: red}\n", "colour"},
      {"format_version: 1\nname: x\nmax_strokes: 0\nholes: [{field: flat, par: 2}]\n",
       "max_strokes"},
      {"format_version: 1\nholes: {field: flat}\n", "holes"},
      {"{{{", "YAML"},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(c.yaml);
    EXPECT_NE(e.find("c.yaml"), std::string::npos) << c.yaml << " -> " << e;
    EXPECT_NE(e.find(c.expected), std::string::npos) << c.yaml << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

// A hole walled off from the tee played six strokes, three of them penalties;
// a key twice or a second YAML document (item 6) was read as the first; a name with a newline
// (item 11) split the progress line. Each is now refused at load, in one line naming the key.
TEST(Course, UnplayableAmbiguousOrMultiLineCoursesAreRefused) {
  const std::string head = "format_version: 1\nname: x\nholes:\n";
  struct Case {
    std::string yaml, expected;
  };
  const Case cases[] = {
      {head + "  - {field: l-shape, hole: [1.0, 1.2], par: 3}\n",
       "c.yaml: holes[0] (tee/hole): the hole (1, 1.2) cannot be reached from the tee (0, 0)"},
      {head + "  - {field: flat, par: 2, par: 3}\n",
       "c.yaml: holes[0].par: duplicate key (a key may appear once per mapping)"},
      {"format_version: 1\nname: x\nname: y\nholes: [{field: flat, par: 2}]\n",
       "c.yaml: name: duplicate key"},
      {head + "  - {field: flat, par: 2}\n---\nholes: [{field: l-shape, par: 9}]\n",
       "c.yaml: a second YAML document at line 5 (expected one"},
      {"format_version: 1\nname: \"a\\nb\"\nholes: [{field: flat, par: 2}]\n",
       "c.yaml: name: expected a name without control characters"},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(c.yaml);
    EXPECT_EQ(e.rfind(c.expected, 0), 0u) << c.yaml << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  // The same lane with the hole round the corner is playable.
  EXPECT_EQ(error_of(head + "  - {field: l-shape, par: 3}\n"), "");
}

TEST(Course, UnknownShippedNameListsTheShippedOnes) {
  try {
    load_course("no-such-course");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("thesis"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_course("/no/such/dir/course.yaml"), Error);
}

}  // namespace
}  // namespace mg::game
