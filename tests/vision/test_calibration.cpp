// Calibration files: what is written reads back to the same bits; bad values name the file and
// the key; a calibration of another rig is refused.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "vision/calibration.hpp"

namespace mg::vision {
namespace {

TEST(Calibration, WrittenFilesReadBackExactly) {
  const Rig rig = load_rig("stereo");
  Calibration c = exact_calibration(rig);
  c.cameras[1].fx += 0.123456789;
  c.cameras[0].dist[3] = 1e-4;
  c.rms_px = {0.1, 0.2};
  c.stereo_rms_px = 0.15;
  c.views = 20;
  const Calibration back = parse_calibration(format_calibration(c), "c.yaml");
  ASSERT_EQ(back.cameras.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.cameras[i].name, c.cameras[i].name);
    EXPECT_EQ(back.cameras[i].fx, c.cameras[i].fx);
    EXPECT_EQ(back.cameras[i].cy, c.cameras[i].cy);
    EXPECT_EQ(back.cameras[i].dist, c.cameras[i].dist);
    EXPECT_EQ(back.cameras[i].R, c.cameras[i].R);
    EXPECT_EQ(back.cameras[i].t, c.cameras[i].t);
    EXPECT_EQ(back.rms_px[i], c.rms_px[i]);
  }
  EXPECT_EQ(back.views, 20);
  EXPECT_NO_THROW(check_calibration_matches(back, rig));
}

TEST(Calibration, BadValuesNameTheFileAndTheKey) {
  const Rig rig = load_rig("stereo");
  const std::string good = format_calibration(exact_calibration(rig));
  const auto error_of = [&](const std::string& from, const std::string& to) -> std::string {
    std::string s = good;
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    s.replace(at, from.size(), to);
    try {
      parse_calibration(s, "c.yaml");
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(error_of("    width: 640", "    width: 640\n    gain: 2")
                .find("c.yaml: cameras[0].gain: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of("    rms_px: 0", "    rms_px: nan")
                .find("c.yaml: cameras[0].rms_px: expected a finite number"),
            std::string::npos);
  EXPECT_NE(error_of("rotation: [", "rotation: [2, ").find("c.yaml: cameras[0].rotation"),
            std::string::npos);
  EXPECT_NE(error_of("    rate_hz: 60", "    rate_hz: 0")
                .find("c.yaml: cameras[0].rate_hz: expected 1..1000"),
            std::string::npos);
  // Another rig's calibration (a camera renamed) is refused.
  Calibration other = parse_calibration(good, "c.yaml");
  other.cameras[1].name = "middle";
  EXPECT_THROW(check_calibration_matches(other, rig), InputError);
}

}  // namespace
}  // namespace mg::vision
