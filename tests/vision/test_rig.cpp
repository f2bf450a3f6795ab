// Rig files: the shipped rig reads; every bad value is one InputError naming the file and the
// key; a camera that sees no part of the lane is refused; the command line says it in one line
// with exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../cli/run_command.hpp"
#include "core/error.hpp"
#include "field/field.hpp"
#include "vision/camera_model.hpp"
#include "vision/rig.hpp"

namespace mg::vision {
namespace {

const char* kGood = R"(format_version: 1
name: test
cameras:
  - {name: a, position: [0.2, 1.0, 2.2], look_at: [1.2, 0, 0], fovy_deg: 50, width: 64,
     height: 48, rate_hz: 60}
  - {name: b, position: [2.2, 1.0, 2.2], look_at: [1.2, 0, 0], fovy_deg: 50, width: 64,
     height: 48, rate_hz: 60, up: [0, 0, 1], latency: 0.02,
     distortion: {k1: -0.05, k2: 0.01}}
)";

std::string with(const std::string& from, const std::string& to) {
  std::string s = kGood;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

std::string error_of(const std::string& text) {
  try {
    parse_rig(text, "rig.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Rig, ShippedRigReadsAndSeesEveryField) {
  const Rig rig = load_rig("stereo");
  ASSERT_EQ(rig.cameras.size(), 2u);
  EXPECT_EQ(rig.cameras[0].name, "left");
  EXPECT_EQ(rig.cameras[1].width, 640);
  for (const char* f : {"flat", "arctan", "bank-shot", "l-shape", "multiple-hills", "regular-hill"})
    EXPECT_NO_THROW(check_rig_sees_field(rig, field::load_field(f))) << f;
}

TEST(Rig, OptionalKeysHaveTheirDefaults) {
  const Rig rig = parse_rig(kGood, "rig.yaml");
  EXPECT_EQ(rig.cameras[0].up, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(rig.cameras[0].latency, 0.0);
  EXPECT_EQ(rig.cameras[1].distortion.k1, -0.05);
  EXPECT_EQ(rig.cameras[1].distortion.p1, 0.0);
}

TEST(Rig, BadValuesNameTheFileAndTheKey) {
  const struct {
    std::string from, to, key;
  } cases[] = {
      {"fovy_deg: 50, width: 64,\n     height: 48, rate_hz: 60}",
       "fovy_deg: 50, width: 64,\n     height: 48, rate_hz: 60, focal: 3}",
       "cameras[0].focal: unknown key"},
      {"fovy_deg: 50", "fovy_deg: .nan", "cameras[0].fovy_deg: expected a number, got '.nan'"},
      {"fovy_deg: 50", "fovy_deg: 170", "cameras[0].fovy_deg: expected 10..120"},
      {"width: 64", "width: 64.5", "cameras[0].width: expected a whole number"},
      {"width: 64", "width: 8", "cameras[0].width: expected 16..4096"},
      {"rate_hz: 60}", "rate_hz: 0}", "cameras[0].rate_hz: expected 1..1000"},
      {"latency: 0.02", "latency: -1", "cameras[1].latency: expected 0..1"},
      {"k1: -0.05", "k1: 2", "cameras[1].distortion.k1: expected -0.5..0.5"},
      {"k2: 0.01", "k2: 0.01, k4: 1", "cameras[1].distortion.k4: unknown key"},
      {"up: [0, 0, 1]", "up: [-1, -1, -2.2]", "cameras[1].up: expected a direction"},
      {"name: b", "name: a", "cameras[1].name: 'a' is used twice"},
      {"look_at: [1.2, 0, 0], fovy_deg: 50, width: 64,\n     height: 48, rate_hz: 60}",
       "fovy_deg: 50, width: 64,\n     height: 48, rate_hz: 60}", "cameras[0].look_at: missing"},
      {"format_version: 1", "format_version: 2", "format_version: expected 1"},
      {"name: test", "name: test\nlens: wide", "lens: unknown key"},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(with(c.from, c.to));
    EXPECT_NE(e.find("rig.yaml: " + c.key), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  EXPECT_NE(error_of("format_version: 1\nname: x\ncameras: []\n")
                .find("cameras: expected a list of 2..8"),
            std::string::npos);
}

TEST(Rig, ACameraThatSeesNoLaneIsRefused) {
  Rig rig = parse_rig(with("look_at: [1.2, 0, 0]", "look_at: [1.2, 5, 5]"), "rig.yaml");
  try {
    check_rig_sees_field(rig, field::load_field("flat"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("rig.yaml: cameras[0]: camera 'a' sees no part of the lane"),
        std::string::npos)
        << e.what();
  }
}

TEST(Rig, ABumpedCameraMovesAndTurns) {
  const Rig rig = parse_rig(kGood, "rig.yaml");
  const Rig bumped = bump_camera(rig, "a", {0.002, 0.0, 0.0}, 0.5, 0.0);
  EXPECT_NEAR(bumped.cameras[0].position[0], rig.cameras[0].position[0] + 0.002, 1e-12);
  EXPECT_EQ(bumped.cameras[1].position, rig.cameras[1].position);  // the other camera stays
  // Half a degree about the vertical moves the old look-at point by about fy tan(0.5 deg)
  // (times the vertical's share of the image's up): several pixels at 48 pixels high.
  const Eigen::Vector3d at(rig.cameras[0].look_at.data());
  const auto before = project(camera_from_spec(rig.cameras[0]), at);
  const auto after = project(camera_from_spec(bumped.cameras[0]), at);
  ASSERT_TRUE(before && after);
  EXPECT_GT((*after - *before).norm(), 0.1);
  EXPECT_LT((*after - *before).norm(), 1.0);
  EXPECT_THROW(bump_camera(rig, "c", {0, 0, 0}, 0.1, 0.0), InputError);
  EXPECT_THROW(bump_camera(rig, "a", {0, 0, 0}, 45.0, 0.0), InputError);
}

TEST(RigCli, ABadRigFileIsOneLineAndExit2) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("mg_vision_rig_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / "bad.yaml";
  std::ofstream(path) << with("fovy_deg: 50", "fovy_deg: .inf");
  for (const std::string& cmd :
       std::vector<std::string>{"vision measure --rig ",
                                "vision calibrate -o " + (dir / "c.yaml").string() + " --rig "}) {
    const auto r = cli::testing::run_minigolf(cmd + path.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(path.string() + ": cameras[0].fovy_deg: expected a number, got '.inf'"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mg::vision
