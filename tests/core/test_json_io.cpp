#include "core/json_io.hpp"

#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg {
namespace {

std::string error_of(std::string_view text) {
  try {
    parse_json(text, "m.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(JsonIo, ParsesAndKeepsEveryKey) {
  const auto j = parse_json(R"({"a": 1, "b": {"a": 2, "c": [{"a": 3}, {"a": 4}]}})", "m.json");
  EXPECT_EQ(j["b"]["c"][1]["a"], 4);  // the same key in different objects is fine
  EXPECT_TRUE(try_parse_json(R"({"a": 1, "b": [1, 2]})").has_value());
}

// nlohmann keeps the last of two equal keys and stops at a NUL byte; both are
// refused, with one line naming the key (or the byte's offset).
TEST(JsonIo, RefusesADuplicateKeyAnywhere) {
  EXPECT_EQ(error_of(R"({"par": 2, "par": 3})"),
            "m.json: duplicate key 'par' (a key may appear once per object)");
  EXPECT_NE(error_of(R"({"a": {"inputs": [1], "inputs": [2]}})").find("duplicate key 'inputs'"),
            std::string::npos);
  EXPECT_NE(error_of(R"([{"x": 1}, {"y": 1, "y": 2}])").find("duplicate key 'y'"),
            std::string::npos);
  EXPECT_FALSE(try_parse_json(R"({"format": "a", "seq": 1, "format": "b"})").has_value());
}

TEST(JsonIo, RefusesANulByteAndWhatFollowsIt) {
  const std::string text = std::string(R"({"a": 1})") + '\0' + "garbage";
  EXPECT_EQ(error_of(text), "m.json: not valid JSON (a NUL byte at offset 8)");
  EXPECT_FALSE(try_parse_json(text).has_value());
  EXPECT_FALSE(try_parse_json("{\"a\": 1").has_value());  // and plain syntax errors
  EXPECT_NE(error_of("{\"a\": 1e999}").find("number out of range"), std::string::npos);
}

TEST(JsonIo, ALongDuplicateKeyIsShownShortAndOnOneLine) {
  const std::string key = "k\\n" + std::string(5000, 'x');  // JSON's escape: a newline
  const std::string e = error_of("{\"" + key + "\": 1, \"" + key + "\": 2}");
  EXPECT_LT(e.size(), 200u) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_NE(e.find("(5002 characters)"), std::string::npos) << e;
}

}  // namespace
}  // namespace mg
