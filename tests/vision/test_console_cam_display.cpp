// The console's normal mode playing a putt from `minigolf vision-cam` as its own process: the
// thesis's stereo computer renders its cameras, finds the ball and the hole and sends them over
// UDP; the console (real time, normal mode) reads nothing else of the scene. A display is needed
// (ctest runs it under xvfb-run as vision_console_under_xvfb).
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>

#include "../cli/run_command.hpp"
#include "../viz/viz_test_util.hpp"
#include "core/io.hpp"
#include "perception/udp.hpp"
#include "small_rig.hpp"

namespace mg::vision {
namespace {

TEST(ConsoleCamDisplay, NormalModeSinksAPuttFromWhatVisionCamSaw) {
  MG_NEED_DISPLAY();
  const auto dir = viz::testing::temp_dir("console_cam");
  const std::string rig = testing::write_small_rig(dir);
  int port = 0;
  {
    const perception::UdpReceiver probe("127.0.0.1", 0);  // a free port, released for the console
    port = probe.port();
  }
  std::ofstream(dir / "console.yaml") << "vision: {vision_port: " << port << "}\n";
  // Normal mode caps the club at 1.5 m/s: a hole at 1.5 m that 1.3-1.5 m/s sinks along x. The
  // console's hit waits at the rest pose until the feed is fresh, so vision-cam's start-up (its
  // OpenGL context) only delays it.
  std::ofstream(dir / "script.txt")
      << "hole 1.5 0.0\nwait 1\nangle 0.0\nspeed 1.4\nhit\nwait 5\nstatus\nquit\n";
  const std::string bin = MINIGOLF_BINARY;
  const std::string cam = bin + " vision-cam --rig " + rig +
                          " --hole 1.5,0 --duration 6 --to 127.0.0.1:" + std::to_string(port) +
                          " > " + (dir / "cam.txt").string() + " 2>&1";
  const std::string console = bin + " console --mode normal --realtime --config " +
                              (dir / "console.yaml").string() + " --script " +
                              (dir / "script.txt").string();
  const auto r = cli::testing::run_command_line("{ " + cam + " & " + console + "; wait; }");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("mode normal, realtime"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Rest -> Hitting"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Hitting -> Braking: the ball was hit"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ball: holed"), std::string::npos) << r.out;
  // What the module perceived came from the cameras: the ball on the tee, the hole at 1.5 m.
  std::smatch m;
  const std::regex seen(R"(perception: fresh, ball \((\S+), (\S+)\), hole \((\S+), (\S+)\))");
  ASSERT_TRUE(std::regex_search(r.out, m, seen)) << r.out;
  EXPECT_NEAR(std::stod(m[1]), 0.0, 0.005);
  EXPECT_NEAR(std::stod(m[2]), 0.0, 0.005);
  EXPECT_NEAR(std::stod(m[3]), 1.5, 0.006);
  EXPECT_NEAR(std::stod(m[4]), 0.0, 0.006);
  const std::regex accepted(R"(accepted (\d+), rejected 0)");
  ASSERT_TRUE(std::regex_search(r.out, m, accepted)) << r.out;
  EXPECT_GT(std::stoi(m[1]), 30);  // the feed ran through the putt
  const std::string cam_out = read_text_file(dir / "cam.txt");
  EXPECT_NE(cam_out.find("vision-cam: sent"), std::string::npos) << cam_out;
}

}  // namespace
}  // namespace mg::vision
