#include "perception/vision_message.hpp"

#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

namespace mg::perception {
namespace {

const VisionLimits kLimits{};

TEST(VisionMessage, RoundTrip) {
  VisionMessage m;
  m.seq = 17;
  m.stamp = 3.25;
  m.ball = {0.0, 0.01, 0.021};
  m.hole = {2.0, -0.1, 0.0};
  const VisionParse p = parse_vision_message(format_vision_message(m), kLimits);
  ASSERT_EQ(p.error, VisionError::kNone);
  EXPECT_EQ(p.message.seq, 17u);
  EXPECT_EQ(p.message.stamp, 3.25);
  EXPECT_EQ(p.message.ball, m.ball);
  EXPECT_EQ(p.message.hole, m.hole);
}

// A key twice (the last one won, "format" too) and a valid datagram followed by
// a NUL byte and garbage (nlohmann stopped at the NUL) are malformed, not accepted.
TEST(VisionMessage, RejectsDuplicateKeysAndANulByte) {
  const std::string ok = R"({"format": "minigolf-vision/1", "seq": 1, "stamp": 0.5, )"
                         R"("ball": [0, 0, 0.02], "hole": [2, 0, 0]})";
  ASSERT_EQ(parse_vision_message(ok, kLimits).error, VisionError::kNone);
  EXPECT_EQ(parse_vision_message(ok + std::string(1, '\0') + "garbage", kLimits).error,
            VisionError::kMalformed);
  EXPECT_EQ(parse_vision_message(R"({"format": "other/9", "format": "minigolf-vision/1", )"
                                 R"("seq": 1, "stamp": 0.5, "ball": [0, 0, 0.02], )"
                                 R"("hole": [2, 0, 0]})",
                                 kLimits)
                .error,
            VisionError::kMalformed);
  EXPECT_EQ(parse_vision_message(R"({"format": "minigolf-vision/1", "seq": 1, "stamp": 0.5, )"
                                 R"("ball": [9, 9, 9], "ball": [0, 0, 0.02], "hole": [2, 0, 0]})",
                                 kLimits)
                .error,
            VisionError::kMalformed);
}

TEST(VisionMessage, RejectsEveryKindOfBadDatagram) {
  const std::string ok_tail = R"("ball": [0, 0, 0.02], "hole": [2, 0, 0]})";
  const std::string head = R"({"format": "minigolf-vision/1", "seq": 1, "stamp": 0.5, )";
  EXPECT_EQ(parse_vision_message(head + ok_tail, kLimits).error, VisionError::kNone);
  EXPECT_EQ(parse_vision_message("", kLimits).error, VisionError::kMalformed);
  EXPECT_EQ(parse_vision_message("{", kLimits).error, VisionError::kMalformed);
  EXPECT_EQ(parse_vision_message("[1,2,3]", kLimits).error, VisionError::kMalformed);
  EXPECT_EQ(parse_vision_message(std::string(600, ' '), kLimits).error, VisionError::kTooLong);
  EXPECT_EQ(
      parse_vision_message(R"({"format": "other/9", "seq": 1, "stamp": 0, )" + ok_tail, kLimits)
          .error,
      VisionError::kWrongFormat);
  EXPECT_EQ(parse_vision_message(
                R"({"format": "minigolf-vision/1", "seq": -1, "stamp": 0, )" + ok_tail, kLimits)
                .error,
            VisionError::kMalformed);
  EXPECT_EQ(parse_vision_message(head + R"("ball": [0, 0], "hole": [2, 0, 0]})", kLimits).error,
            VisionError::kMalformed);
  EXPECT_EQ(
      parse_vision_message(head + R"("ball": [0, "a", 0], "hole": [2, 0, 0]})", kLimits).error,
      VisionError::kMalformed);
  EXPECT_EQ(
      parse_vision_message(head + R"("ball": [0, NaN, 0], "hole": [2, 0, 0]})", kLimits).error,
      VisionError::kMalformed);
  EXPECT_EQ(
      parse_vision_message(head + R"("ball": [0, 1e999, 0], "hole": [2, 0, 0]})", kLimits).error,
      VisionError::kMalformed);
  EXPECT_EQ(parse_vision_message(head + R"("ball": [0, 0, 0], "hole": [20, 0, 0]})", kLimits).error,
            VisionError::kOutOfRange);
}

// Random bytes and random truncations of a good message never crash and never pass as valid
// unless they still are a complete, in-range message.
TEST(VisionMessage, FuzzedDatagramsNeverCrash) {
  VisionMessage m;
  m.ball = {0.1, 0.0, 0.02};
  m.hole = {2.0, 0.2, 0.0};
  const std::string good = format_vision_message(m);
  std::mt19937_64 rng(7);
  for (int i = 0; i < 5000; ++i) {
    std::string s = good.substr(0, rng() % (good.size() + 1));
    if (i % 2 && !s.empty()) s[rng() % s.size()] = static_cast<char>(rng() % 256);
    const VisionParse p = parse_vision_message(s, kLimits);
    if (p.error == VisionError::kNone) {
      EXPECT_TRUE(std::isfinite(p.message.ball[0] + p.message.hole[1] + p.message.stamp));
    }
  }
}

}  // namespace
}  // namespace mg::perception
