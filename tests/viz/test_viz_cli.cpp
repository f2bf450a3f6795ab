// view | render | plot end to end (the built binary). Drawing tests need a display (xvfb-run).
#include <gtest/gtest.h>

#include <fstream>

#include "../cli/run_command.hpp"
#include "../slow_test.hpp"
#include "viz/image.hpp"
#include "viz_test_util.hpp"

namespace mg::viz {
namespace {

using cli::testing::count_lines;
using cli::testing::run_minigolf;

/// run_minigolf with a prefix such as "env PATH=..." before the binary; stdout only (stderr to it).
cli::testing::CommandResult run_minigolf_env(const std::string& prefix, const std::string& args) {
  cli::testing::CommandResult r;
  const std::string cmd = prefix + " " + std::string(MINIGOLF_BINARY) + " " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe)) r.out += buf;
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

void write(const std::filesystem::path& p, const std::string& text) {
  std::ofstream f(p);
  f << text;
}

TEST(ViewCliDisplay, ViewerRunsAScriptedHitAndQuits) {
  MG_NEED_DISPLAY();
  const auto dir = testing::temp_dir("view");
  write(dir / "hit.txt", "speed 0.8\nhit\nwait 2.5\nstatus\nquit\n");
  const auto shot = dir / "last.png";
  const auto r = run_minigolf("view --field flat --size 320x240 --script " + q(dir / "hit.txt") +
                              " --screenshot " + q(shot));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("Rest -> Hitting"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Hitting -> Braking: the ball was hit"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bye"), std::string::npos) << r.out;
  const Image img = read_png(shot);
  EXPECT_EQ(img.width, 320);
  EXPECT_EQ(img.height, 240);
  long bright = 0;  // not a blank frame: the lit lane and the overlay text
  for (std::size_t i = 0; i < img.rgb.size(); i += 3) bright += img.rgb[i + 1] > 60;
  EXPECT_GT(bright, 320 * 240 / 10);
}

TEST(ViewCliDisplay, RenderWritesTheVideoAndTheFilmstrip) {
  MG_NEED_DISPLAY();
  const auto dir = testing::temp_dir("render_cli");
  const auto r = run_minigolf(
      "render --field flat --angle 0.05 --speed 0.8 --size 160x120 --fps 10 -o " + q(dir / "hit"));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("filmstrip:"), std::string::npos) << r.out;
  const Image strip = read_png(dir / "hit-filmstrip.png");
  EXPECT_EQ(strip.height, 120);
  EXPECT_EQ(strip.width, 5 * 160 + 16);
  EXPECT_TRUE(std::filesystem::exists(dir / "hit.mp4") ||
              std::filesystem::exists(dir / "hit-frames"));
}

TEST(ViewCliDisplay, RenderWithoutFfmpegWritesPngFrames) {
  MG_NEED_DISPLAY();
  const auto dir = testing::temp_dir("render_noffmpeg");
  const auto r = run_minigolf_env(
      "env PATH=/nonexistent",
      "render --field flat --angle 0 --speed 0.8 --size 160x120 --fps 5 -o " + q(dir / "hit"));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("ffmpeg not found"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "hit.mp4"));
  int frames = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir / "hit-frames")) {
    const Image img = read_png(e.path());
    EXPECT_EQ(img.width, 160);
    ++frames;
  }
  EXPECT_GT(frames, 10);  // 5 fps over about 3 s of simulated time
}

/// A one-hole course on the shipped flat field (the oracle plays it in a few seconds).
std::filesystem::path tiny_course(const std::filesystem::path& dir) {
  const auto path = dir / "tiny.yaml";
  write(path,
        "format_version: 1\nname: tiny\nmax_strokes: 4\n"
        "holes: [{field: flat, tee: [0.2, 0.0], hole: [1.2, 0.1], par: 2}]\n");
  return path;
}

TEST(ViewCliDisplay, RenderCourseFilmsTheHoleAndItsFilmstrip) {
  MG_NEED_DISPLAY();
  const auto dir = testing::temp_dir("render_course");
  const auto r = run_minigolf("render --course " + q(tiny_course(dir)) +
                              " --player oracle --size 160x120 --fps 5 -o " + q(dir / "hole"));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("hole 1 of tiny (flat, par 2), oracle"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("filmstrip:"), std::string::npos) << r.out;
  const Image strip = read_png(dir / "hole-filmstrip.png");
  EXPECT_EQ(strip.height, 120);
  EXPECT_EQ((strip.width + 4) % (160 + 4), 0) << strip.width;  // one picture per stroke
  EXPECT_TRUE(std::filesystem::exists(dir / "hole.mp4") ||
              std::filesystem::exists(dir / "hole-frames"));
}

TEST(ViewCliDisplay, RenderCourseWithoutFfmpegWritesPngFrames) {
  MG_NEED_DISPLAY();
  const auto dir = testing::temp_dir("render_course_frames");
  const auto r = run_minigolf_env(
      "env PATH=/nonexistent", "render --course " + q(tiny_course(dir)) +
                                   " --player oracle --size 160x120 --fps 4 -o " + q(dir / "hole"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("ffmpeg not found"), std::string::npos) << r.out;
  int frames = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir / "hole-frames")) {
    EXPECT_EQ(read_png(e.path()).width, 160);
    ++frames;
  }
  EXPECT_GE(frames, 3 + 2 + 1);  // aim (0.6 s), hold (0.5 s), at least one rolling frame
  EXPECT_TRUE(std::filesystem::exists(dir / "hole-filmstrip.png"));
}

TEST(ViewCli, RenderCourseRejectsBadInputsInOneLine) {
  const auto dir = testing::temp_dir("render_course_bad");
  const std::string course = q(tiny_course(dir));
  const std::string out = " -o " + q(dir / "hole");
  for (const std::string& args :
       {"--course nowhere" + out, "--course " + course + " --hole 2" + out,
        "--course " + course + " --hole 0" + out, "--course " + course + " --hole 1,0" + out,
        "--course " + course + " --player nobody" + out,
        "--course " + course + " --angle 0 --speed 1" + out,
        "--course " + course + " --field flat" + out, "--field flat --player oracle" + out,
        "--course " + course + " --size 161x120" + out,
        "--course " + course + " -o /nonexistent/folder/hole"}) {
    // Without a display too: the inputs are checked before the window opens.
    const auto r = run_minigolf("render " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "hole-filmstrip.png"));
}

TEST(ViewCli, WithoutAScreenViewAndRenderSayWhyInOneLine) {
  // Unset DISPLAY for the child (env -u): as on a machine without a screen and without Xvfb.
  for (const char* cmd : {"view --field flat --script /dev/null",
                          "render --field flat --angle 0 --speed 1 -o /tmp/mg_viz_nodisplay",
                          "render --course thesis --player oracle -o /tmp/mg_viz_nodisplay"}) {
    const auto r = run_minigolf_env("env -u DISPLAY -u WAYLAND_DISPLAY", cmd);
    const std::string& out = r.out;
    EXPECT_EQ(r.exit_code, 1) << "crashed or wrong code: " << out;
    EXPECT_EQ(count_lines(out), 1) << out;
    EXPECT_NE(out.find("no display"), std::string::npos) << out;
    EXPECT_NE(out.find("xvfb-run"), std::string::npos) << out;
  }
}

TEST(ViewCli, RenderRejectsBadRequestsBeforeDrawing) {
  for (const char* args : {"--field flat --angle 0 -o /tmp/x",
                           "--field flat --angle 0 --speed 1 --size 321x240 -o /tmp/x",
                           "--field flat --angle 0 --speed 1 --camera nowhere -o /tmp/x",
                           "--field nowhere --angle 0 --speed 1 -o /tmp/x",
                           "--field flat --angle 2 --speed 1 -o /tmp/x",
                           "--field flat --angle 0 --speed 1 --hole 9,9 -o /tmp/x",
                           "--field flat --angle 0 --speed 1 -o /nonexistent/folder/hit"}) {
    const auto r = run_minigolf("render " + std::string(args));
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
  }
  // A folder where the MP4 would go is never replaced.
  const auto dir = testing::temp_dir("render_isdir");
  std::filesystem::create_directories(dir / "hit.mp4");
  const auto r = run_minigolf("render --field flat --angle 0 --speed 1 -o " + q(dir / "hit"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::is_directory(dir / "hit.mp4"));
}

/// A shipped data file, by absolute path (the tests run in the build folder).
std::string shipped(const std::string& rel) {
  return q(std::string(MINIGOLF_TEST_DATA_DIR) + "/../../data/" + rel);
}

bool nonempty_png(const std::filesystem::path& p) {
  const Image img = read_png(p);
  return img.width > 100 && img.height > 100;
}

TEST(PlotCli, DsAndStrengthFiguresOfTheShippedModel) {
  MG_SLOW_TEST();
  const auto dir = testing::temp_dir("plot_ds");
  auto r = run_minigolf("plot ds -o " + q(dir / "ds.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nonempty_png(dir / "ds.png"));
  r = run_minigolf("plot ds --plane xy --data-dir " + q(dir / "data") + " -o " +
                   q(dir / "ds_xy.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "data" / "ds_gmm.csv"));
  r = run_minigolf("plot strength -o " + q(dir / "strength.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nonempty_png(dir / "strength.png"));
}

TEST(PlotCli, FieldAndModelFigures) {
  const auto dir = testing::temp_dir("plot_field");
  auto r = run_minigolf("plot field --field regular-hill --shot 0.05,1.2 --shot -0.05,1.4 -o " +
                        q(dir / "field.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nonempty_png(dir / "field.png"));
  r = run_minigolf("train " + shipped("datasets/flat.csv") +
                   " --inputs xi_y --outputs angle --restarts 2 -o " + q(dir / "m.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_minigolf("plot model --model " + q(dir / "m.json") + " --data " +
                   shipped("datasets/flat.csv") + " --validation " +
                   shipped("datasets/flat-validation.csv") + " -o " + q(dir / "model.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nonempty_png(dir / "model.png"));
}

TEST(PlotCli, RoundWritesOnePngPerHoleOfASmallCourse) {
  const auto dir = testing::temp_dir("plot_round");
  const auto r = run_minigolf("plot round --course " + q(tiny_course(dir)) +
                              " --player oracle --seeds 2 --data-dir " + q(dir / "data") + " -o " +
                              q(dir / "figs"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("hole 1: flat, par 2"), std::string::npos) << r.out;
  EXPECT_TRUE(nonempty_png(dir / "figs" / "tiny-hole1.png"));
  EXPECT_FALSE(std::filesystem::exists(dir / "figs" / "tiny-hole2.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "data" / "tiny-hole1_paths.csv"));
}

TEST(PlotCli, FieldDrawsObstacles) {
  const auto dir = testing::temp_dir("plot_obstacles");
  const auto r = run_minigolf("plot field --field bank-shot --shot 0.3,1.5 --data-dir " +
                              q(dir / "data") + " -o " + q(dir / "field.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("1 obstacles"), std::string::npos) << r.out;
  EXPECT_TRUE(nonempty_png(dir / "field.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "data" / "field_obstacles.csv"));
}

TEST(PlotCli, RoundRejectsBadInputsInOneLine) {
  const auto dir = testing::temp_dir("plot_round_bad");
  const std::string course = q(tiny_course(dir));
  write(dir / "file", "x");
  for (const std::string& args : {"--course nowhere -o " + q(dir / "figs"),
                                  "--course " + course + " --seeds 0 -o " + q(dir / "figs"),
                                  "--course " + course + " --player nobody -o " + q(dir / "figs"),
                                  "--course " + course + " --stem a/b -o " + q(dir / "figs"),
                                  "--course " + course + " -o " + q(dir / "file")}) {
    const auto r = run_minigolf("plot round " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "figs"));
}

TEST(PlotCli, MissingOrBrokenInputsAreOneLineExitTwo) {
  const auto dir = testing::temp_dir("plot_bad");
  write(dir / "broken.csv", "demo,t,x,y,z,vx,vy,vz\n0,0,abc,0,0,0,0,0\n");
  write(dir / "broken.json", "{\"priors\": [");
  const std::string data = std::string(MINIGOLF_TEST_DATA_DIR) + "/learning/";
  for (const std::string& args :
       {"ds --demos /nonexistent.csv -o " + q(dir / "a.png"),
        "ds --demos " + q(dir / "broken.csv") + " -o " + q(dir / "a.png"),
        "ds --hitting-model " + q(dir / "broken.json") + " -o " + q(dir / "a.png"),
        "ds --plane yz -o " + q(dir / "a.png"), "strength --speeds 1,abc -o " + q(dir / "a.png"),
        "strength --hitting-model /nonexistent.json -o " + q(dir / "a.png"),
        "field --field nowhere -o " + q(dir / "a.png"),
        "field --field flat --shot 0,nan -o " + q(dir / "a.png"),
        "field --field flat --hole 99,0 -o " + q(dir / "a.png"),
        "model --model /nonexistent.json --data " + shipped("datasets/flat.csv") + " -o " +
            q(dir / "a.png"),
        "model --model " + q(data + "truncated_model.json") + " --data " +
            shipped("datasets/flat.csv") + " -o " + q(dir / "a.png"),
        "model --model " + q(dir / "broken.json") + " --data " + shipped("datasets/flat.csv") +
            " -o " + q(dir / "a.png")}) {
    const auto r = run_minigolf("plot " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "a.png")) << args;
  }
}

}  // namespace
}  // namespace mg::viz
