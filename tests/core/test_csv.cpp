#include "core/csv.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg {
namespace {

TEST(Csv, ParsesHeaderAndRows) {
  const CsvTable t = parse_csv("a,b\n1,2.5\n# comment\n\n-3,4e-2\n", "mem");
  ASSERT_EQ(t.header.size(), 2u);
  ASSERT_EQ(t.num_rows(), 2u);
  EXPECT_DOUBLE_EQ(t.rows[1][0], -3.0);
  EXPECT_DOUBLE_EQ(t.column("b")[1], 0.04);
}

TEST(Csv, RejectsTextNanEmptyAndShortRows) {
  EXPECT_THROW(parse_csv("", "mem"), InputError);
  EXPECT_THROW(parse_csv("a,b\n1,x\n", "mem"), InputError);
  EXPECT_THROW(parse_csv("a,b\n1,nan\n", "mem"), InputError);
  EXPECT_THROW(parse_csv("a,b\n1\n", "mem"), InputError);
  EXPECT_THROW(parse_csv("a,a\n1,2\n", "mem"), InputError);
  const CsvTable t = parse_csv("a,b\n1,2\n", "mem");
  EXPECT_THROW(t.column("c"), InputError);
}

TEST(Csv, ErrorNamesSourceLineAndColumn) {
  try {
    parse_csv("a,b\n1,2\n3,oops\n", "data.csv");
    FAIL();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("data.csv:3"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'b'"), std::string::npos) << msg;
  }
}

TEST(Csv, FormatRoundTripsBits) {
  const double x = 0.1 + 0.2;
  const CsvTable t = parse_csv(format_csv({"x"}, {{x}}), "mem");
  EXPECT_EQ(t.rows[0][0], x);
}

}  // namespace
}  // namespace mg
