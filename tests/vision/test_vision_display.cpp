// The cameras on rendered images (a display: ctest runs these under xvfb-run as
// vision_under_xvfb). Small images keep them fast: a 320x240 copy of the shipped rig.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <opencv2/videoio.hpp>

#include "../cli/run_command.hpp"
#include "../viz/viz_test_util.hpp"
#include "core/io.hpp"
#include "perception/udp.hpp"
#include "perception/vision_message.hpp"
#include "sim_backend/arm_mujoco.hpp"
#include "sim_backend/full_system.hpp"
#include "small_rig.hpp"
#include "system/system.hpp"
#include "vision/calibrate.hpp"
#include "vision/camera_perception.hpp"
#include "vision/still_scene.hpp"
#include "viz/renderer.hpp"

namespace mg::vision {
namespace {

using testing::small_rig;

struct Scene {
  system::System sys{system::load_config("", "flat")};
  viz::GlWindow window{64, 64, false, "test"};
  Rig rig = small_rig();
  RigRenderer renderer{sys.arm_world(), rig};
  sim::DataPtr d = sys.arm_world().make_data();
  const sim::World& world() const { return sys.arm_world(); }
};

TEST(VisionDisplay, TriangulatesBallAndHoleWithinMillimetres) {
  MG_NEED_DISPLAY();
  Scene s;
  const StereoModel model(exact_calibration(s.rig), s.sys.field());
  double worst_ball = 0, worst_hole = 0;
  for (const std::array<double, 2> ball :
       {std::array<double, 2>{0.0, 0.0}, {1.0, 0.3}, {2.3, -0.4}, {0.6, -0.45}}) {
    place_still_scene(s.world(), s.d.get(), ball, {2.0, 0.1});
    StereoData data(model);
    const StillMeasurement m = measure_still(s.renderer, model, data, s.d.get());
    ASSERT_EQ(m.ball.views, 2) << ball[0] << "," << ball[1];
    ASSERT_EQ(m.hole.views, 2);
    // The detections lie on the truth's projection (sub-pixel).
    for (std::size_t i = 0; i < 2; ++i) {
      const auto px = project(s.renderer.truth(static_cast<int>(i)), m.true_ball);
      EXPECT_LT((m.ball.blobs[i].pixel - *px).norm(), 0.5) << i;
    }
    worst_ball = std::max(worst_ball, (m.ball.point - m.true_ball).norm());
    worst_hole = std::max(worst_hole, (m.hole.point - m.true_hole).norm());
    EXPECT_LT(m.ball.reprojection_px, 1.0);
  }
  std::printf("320x240: worst ball error %.2f mm, hole %.2f mm\n", 1e3 * worst_ball,
              1e3 * worst_hole);
  EXPECT_LT(worst_ball, 0.004);
  EXPECT_LT(worst_hole, 0.006);
}

TEST(VisionDisplay, CalibrationRecoversTheRig) {
  MG_NEED_DISPLAY();
  Scene s;
  const auto& f = s.world().field();
  place_still_scene(s.world(), s.d.get(), f.tee, f.hole.position);
  CalibrateOptions o;
  o.views = 15;
  o.square = 0.1;  // 10 pixels or more at 320x240
  const CalibrateReport rep = calibrate_rig(s.renderer, s.d.get(), s.rig, o);
  const Calibration& c = rep.calibration;
  ASSERT_EQ(c.cameras.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const CameraModel& truth = s.renderer.truth(i);
    const CameraModel& got = c.cameras[static_cast<std::size_t>(i)];
    std::printf(
        "%s: rms %.3f px, fx %.2f/%.2f, cx %.2f/%.2f, cy %.2f/%.2f, k1 %.4f/%.4f, centre off %.1f "
        "mm\n",
        got.name.c_str(), c.rms_px[static_cast<std::size_t>(i)], got.fx, truth.fx, got.cx, truth.cx,
        got.cy, truth.cy, got.dist[0], truth.dist[0], 1e3 * (got.centre() - truth.centre()).norm());
    EXPECT_LT(c.rms_px[static_cast<std::size_t>(i)], 0.3);
    EXPECT_NEAR(got.fx / truth.fx, 1.0, 0.01);
    EXPECT_NEAR(got.fy / truth.fy, 1.0, 0.01);
    EXPECT_NEAR(got.cx, truth.cx, 3.0);
    EXPECT_NEAR(got.cy, truth.cy, 3.0);
    EXPECT_NEAR(got.dist[0], truth.dist[0], 0.03);
    EXPECT_LT((got.centre() - truth.centre()).norm(), 0.02);
  }
  EXPECT_NEAR(rep.stereo_baseline, 2.0, 0.02);
  // With the calibration (the belief), a ball is still found within a few millimetres.
  const StereoModel model(c, s.sys.field());
  place_still_scene(s.world(), s.d.get(), {1.3, 0.2}, f.hole.position);
  StereoData data(model);
  const StillMeasurement m = measure_still(s.renderer, model, data, s.d.get());
  ASSERT_EQ(m.ball.views, 2);
  EXPECT_LT((m.ball.point - m.true_ball).norm(), 0.008);
}

/// True when the straight line from `from` to `to` meets a geom other than the ball's first.
bool blocked(const sim::World& w, const mjData* d, const Eigen::Vector3d& from,
             const Eigen::Vector3d& to) {
  const Eigen::Vector3d dir = to - from;
  mjtNum pnt[3] = {from.x(), from.y(), from.z()}, vec[3] = {dir.x(), dir.y(), dir.z()};
  int geom = -1;
  const mjtNum t = mj_ray(w.model(), d, pnt, vec, nullptr, 1, -1, &geom);
  return t >= 0 && t < 0.97 && geom != w.ids().ball_geom;
}

TEST(VisionDisplay, TheArmInFrontOfTheBallInOneCameraLeavesTheOther) {
  MG_NEED_DISPLAY();
  Scene s;
  const StereoModel model(exact_calibration(s.rig), s.sys.field());
  const auto& f = s.world().field();
  const Eigen::Vector3d c0 = s.renderer.truth(0).centre(), c1 = s.renderer.truth(1).centre();
  // Balls whose centre the arm hides from the left camera (not from the right one): each is
  // still placed within a centimetre, by the right camera alone where the left sees nothing or
  // a sliver (a partly hidden ball's centre is off).
  int cases = 0, one_view = 0;
  for (double x = -0.25; x <= 0.8 && cases < 8; x += 0.02)
    for (double y = -0.55; y <= 0.0 && cases < 8; y += 0.02) {
      if (std::hypot(x - f.hole.position[0], y - f.hole.position[1]) < 0.2) continue;
      place_still_scene(s.world(), s.d.get(), {x, y}, f.hole.position);
      const Eigen::Vector3d b(x, y, f.height(x, y) + f.ball.radius);
      if (!blocked(s.world(), s.d.get(), c0, b) || blocked(s.world(), s.d.get(), c1, b)) continue;
      ++cases;
      StereoData data(model);
      const StillMeasurement m = measure_still(s.renderer, model, data, s.d.get());
      std::printf(
          "ball at (%.2f, %.2f) behind the arm for the left camera: left %s, %d view(s), error "
          "%.1f mm\n",
          x, y,
          !m.ball.blobs[0].found ? "sees nothing"
          : m.ball.partial       ? "sees a sliver"
                                 : "sees it",
          m.ball.views, 1e3 * (m.ball.point - m.true_ball).norm());
      EXPECT_TRUE(m.ball.blobs[1].found);
      ASSERT_GE(m.ball.views, 1);
      EXPECT_LT((m.ball.point - m.true_ball).norm(), 0.01);
      if (m.ball.views == 1) ++one_view;
    }
  EXPECT_GE(cases, 3) << "too few ball positions behind the arm for the left camera";
  EXPECT_GE(one_view, 1);
}

TEST(VisionDisplay, TheClubBehindTheBallDoesNotMoveIt) {
  MG_NEED_DISPLAY();
  Scene s;
  const StereoModel model(exact_calibration(s.rig), s.sys.field());
  const auto& f = s.world().field();
  place_still_scene(s.world(), s.d.get(), f.tee, f.hole.position);
  // The arm at the rest pose of a straight hit: the club head a few centimetres behind the ball.
  robot::set_joint_positions(robot::find_arm_ids(s.world().model()), s.d.get(),
                             control::rest_joint_positions(s.sys.module(), 0.0));
  mj_forward(s.world().model(), s.d.get());
  StereoData data(model);
  const StillMeasurement m = measure_still(s.renderer, model, data, s.d.get());
  ASSERT_GE(m.ball.views, 1);
  EXPECT_LT((m.ball.point - m.true_ball).norm(), 0.005) << m.ball.views;
}

TEST(VisionDisplay, ALostBallGoesStaleAndABallInTheCupIsReported) {
  MG_NEED_DISPLAY();
  Scene s;
  const StereoModel model(exact_calibration(s.rig), s.sys.field());
  const auto& f = s.world().field();
  place_still_scene(s.world(), s.d.get(), {1.0, 0.2}, f.hole.position);
  CameraPerception eyes(s.renderer, model, s.d.get());
  const double latency = s.rig.cameras[0].latency;
  perception::Perceived p = eyes.perceive(0.0);
  EXPECT_FALSE(p.fresh);  // nothing released before the latency
  double t = 0.0;
  for (; t < 0.1; t += 0.01) p = eyes.perceive(t);
  ASSERT_TRUE(p.fresh);
  EXPECT_NEAR(p.ball[0], 1.0, 0.004);
  EXPECT_NEAR(p.ball[1], 0.2, 0.004);
  EXPECT_NEAR(p.hole[0], f.hole.position[0], 0.006);
  // The ball vanishes (taken off the lane): the estimate ages and goes stale; never fresh again.
  sim::BallState b = s.world().ball_state(s.d.get());
  b.qpos[2] = -1.0;
  s.world().set_ball_state(s.d.get(), b);
  mj_forward(s.world().model(), s.d.get());
  double stale_at = -1;
  for (; t < 0.5; t += 0.01) {
    p = eyes.perceive(t);
    if (!p.fresh && stale_at < 0) stale_at = t;
    if (stale_at >= 0) {
      EXPECT_FALSE(p.fresh) << t;
    }
  }
  ASSERT_GE(stale_at, 0.1);
  EXPECT_LE(stale_at, 0.1 + model.config.max_age + latency + 0.04);
  EXPECT_FALSE(eyes.estimate().ball_in_cup);  // it vanished far from the hole
  // A ball that rolls onto the cup and drops in is reported in the cup.
  const auto hole = s.world().hole_position(s.d.get());
  place_still_scene(s.world(), s.d.get(), hole, hole);
  for (double end = t + 0.15; t < end; t += 0.01) p = eyes.perceive(t);
  ASSERT_TRUE(p.fresh);
  b = s.world().ball_state(s.d.get());
  b.qpos[2] = f.height(hole[0], hole[1]) - f.hole.depth + f.ball.radius;
  s.world().set_ball_state(s.d.get(), b);
  mj_forward(s.world().model(), s.d.get());
  for (double end = t + 0.3; t < end; t += 0.01) p = eyes.perceive(t);
  EXPECT_FALSE(p.fresh);
  EXPECT_TRUE(eyes.estimate().ball_in_cup);
}

}  // namespace
}  // namespace mg::vision

namespace mg::vision {
namespace {

// A rig that sees the hole but not the ball on the tee: the module never has a fresh ball, so it
// never hits (the putt is refused; the club does not touch the ball). With the shipped rig at
// 320x240 the same putt is played as with the simulator's truth.
TEST(VisionCliDisplay, APuttWithCamerasHitsOnlyWhatTheCamerasSee) {
  MG_NEED_DISPLAY();
  const auto dir = viz::testing::temp_dir("vision_cli");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  const std::string far = write("far.yaml", R"(format_version: 1
name: far
cameras:
  - {name: left, position: [1.6, 1.0, 1.2], look_at: [2.2, 0, 0], fovy_deg: 40, width: 160,
     height: 120, rate_hz: 60}
  - {name: right, position: [2.8, 1.0, 1.2], look_at: [2.2, 0, 0], fovy_deg: 40, width: 160,
     height: 120, rate_hz: 60}
)");
  const auto blind = cli::testing::run_minigolf(
      "putt --angle 0 --speed 1.0 --perception camera --json --rig " + far);
  EXPECT_EQ(blind.exit_code, 2) << blind.out << blind.err;
  EXPECT_NE(blind.err.find("the module refused the hit request"), std::string::npos) << blind.err;

  const std::string rig = testing::write_small_rig(dir);
  const auto truth = cli::testing::run_minigolf("putt --angle 0 --speed 1.2 --json");
  const auto seen = cli::testing::run_minigolf(
      "putt --angle 0 --speed 1.2 --json --perception camera --rig " + rig);
  ASSERT_EQ(truth.exit_code, 0) << truth.err;
  ASSERT_EQ(seen.exit_code, 0) << seen.err;
  const auto t = nlohmann::json::parse(truth.out), c = nlohmann::json::parse(seen.out);
  EXPECT_EQ(c["perception"]["ball_lost"], 0);
  EXPECT_GT(c["perception"]["ball_stereo"].get<int>(), 30);
  EXPECT_EQ(c["sunk"], t["sunk"]);
  EXPECT_NEAR(c["rest_position"][0].get<double>(), t["rest_position"][0].get<double>(), 0.05);
  EXPECT_NEAR(c["rest_position"][1].get<double>(), t["rest_position"][1].get<double>(), 0.05);
}

// `evaluate --perception camera`: every thread has its own cameras (its own OpenGL context), and
// the evaluation is the same to the bit on one thread and on two; it plays what the truth plays.
// (A 320x240 copy of the shipped rig at 30 Hz: half the frames to render.)
TEST(VisionCliDisplay, EvaluateWithCamerasHasTheSameBitsOnOneAndTwoThreads) {
  MG_NEED_DISPLAY();
  const auto dir = viz::testing::temp_dir("vision_evaluate");
  const std::string rig = testing::write_small_rig(dir, 30);
  const std::string model = (dir / "flat.json").string();
  ASSERT_EQ(
      cli::testing::run_minigolf("train --method gpr " +
                                 (data_dir() / "datasets" / "flat.csv").string() + " -o " + model)
          .exit_code,
      0);
  const std::string evaluate =
      "evaluate --field flat --situations 2 --seed 4 --no-oracle --json --model " + model;
  const auto one =
      cli::testing::run_minigolf(evaluate + " --perception camera --threads 1 --rig " + rig);
  const auto two =
      cli::testing::run_minigolf(evaluate + " --perception camera --threads 2 --rig " + rig);
  const auto truth = cli::testing::run_minigolf(evaluate + " --threads 2");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  ASSERT_EQ(two.exit_code, 0) << two.err;
  ASSERT_EQ(truth.exit_code, 0) << truth.err;
  EXPECT_EQ(one.out, two.out);
  const auto c = nlohmann::json::parse(one.out), t = nlohmann::json::parse(truth.out);
  EXPECT_EQ(c["sunk"], t["sunk"]);
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_NEAR(c["rows"][i]["closest_approach"].get<double>(),
                t["rows"][i]["closest_approach"].get<double>(), 0.05)
        << i;
}

// vision-cam: the rendered cameras' ball and hole arrive as minigolf-vision/1 datagrams; the
// frames it wrote, replayed without rendering, give the same positions.
TEST(VisionCliDisplay, VisionCamPublishesWhatItSeesAndReplaysItsFrames) {
  MG_NEED_DISPLAY();
  const auto dir = viz::testing::temp_dir("vision_cam");
  const std::string rig = testing::write_small_rig(dir);
  const auto receive = [](perception::UdpReceiver& rx) {
    std::vector<perception::VisionMessage> got;
    std::array<char, 600> buf{};
    while (auto n = rx.receive(buf)) {
      const auto p = perception::parse_vision_message(std::string_view(buf.data(), *n), {});
      EXPECT_EQ(p.error, perception::VisionError::kNone);
      got.push_back(p.message);
    }
    return got;
  };
  perception::UdpReceiver rx("127.0.0.1", 0);
  const std::string to = " --fast --duration 0.2 --to 127.0.0.1:" + std::to_string(rx.port());
  const auto live = cli::testing::run_minigolf("vision-cam --rig " + rig + to + " --frames " +
                                               (dir / "frames").string());
  ASSERT_EQ(live.exit_code, 0) << live.err;
  const auto a = receive(rx);
  ASSERT_EQ(a.size(), 12u) << live.out;  // 0.2 s at 60 Hz, every frame fresh
  for (const auto& m : a) {
    EXPECT_NEAR(m.ball[0], 0.0, 0.004);  // the ball on the tee
    EXPECT_NEAR(m.ball[1], 0.0, 0.004);
    EXPECT_NEAR(m.hole[0], 2.0, 0.006);
  }
  const auto replay = cli::testing::run_minigolf("vision-cam --rig " + rig + to + " --replay " +
                                                 (dir / "frames").string());
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  const auto b = receive(rx);
  ASSERT_EQ(b.size(), a.size()) << replay.out;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(b[k].ball, a[k].ball);
    EXPECT_EQ(b[k].hole, a[k].hole);
  }
}

// vision-cam --video: the pairs a rendered run wrote, made into one MJPG video per camera by
// cv::VideoWriter, give the same ball and hole within millimetres (JPEG's loss) as the live run.
TEST(VisionCliDisplay, VisionCamReadsOneVideoPerCamera) {
  MG_NEED_DISPLAY();
  const auto dir = viz::testing::temp_dir("vision_video");
  const std::string rig = testing::write_small_rig(dir);
  perception::UdpReceiver rx("127.0.0.1", 0);
  const auto receive = [&rx] {
    std::vector<perception::VisionMessage> got;
    std::array<char, 600> buf{};
    while (auto n = rx.receive(buf))
      got.push_back(perception::parse_vision_message(std::string_view(buf.data(), *n), {}).message);
    return got;
  };
  const std::string to = " --fast --duration 0.1 --to 127.0.0.1:" + std::to_string(rx.port());
  const auto live = cli::testing::run_minigolf("vision-cam --rig " + rig + to + " --frames " +
                                               (dir / "frames").string());
  ASSERT_EQ(live.exit_code, 0) << live.err;
  const auto a = receive();
  ASSERT_EQ(a.size(), 6u) << live.out;
  std::string videos;
  for (const std::string camera : {"left", "right"}) {
    const auto path = dir / (camera + ".avi");
    cv::VideoWriter writer(path.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 60.0,
                           cv::Size(320, 240));
    ASSERT_TRUE(writer.isOpened()) << "OpenCV cannot write MJPG AVI";
    for (int k = 0; k < 6; ++k) {
      const viz::Image image =
          viz::read_png(dir / "frames" / fmt::format("frame-{:05d}-{}.png", k, camera));
      cv::Mat bgr(image.height, image.width, CV_8UC3);
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
          const std::uint8_t* p = image.pixel(x, y);
          bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(p[2], p[1], p[0]);
        }
      writer.write(bgr);
    }
    writer.release();
    videos += (videos.empty() ? "" : ",") + path.string();
  }
  const auto played =
      cli::testing::run_minigolf("vision-cam --rig " + rig + to + " --video " + videos);
  ASSERT_EQ(played.exit_code, 0) << played.err;
  EXPECT_NE(played.out.find("from 6 stereo frames"), std::string::npos) << played.out;
  const auto b = receive();
  ASSERT_EQ(b.size(), a.size()) << played.out;
  for (std::size_t k = 0; k < a.size(); ++k)
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(b[k].ball[static_cast<std::size_t>(i)], a[k].ball[static_cast<std::size_t>(i)],
                  0.002);
      EXPECT_NEAR(b[k].hole[static_cast<std::size_t>(i)], a[k].hole[static_cast<std::size_t>(i)],
                  0.003);
    }
  // One file, a missing one, with --replay: one line, exit 2.
  for (const std::string& args :
       {" --video " + (dir / "left.avi").string(),
        " --video " + (dir / "left.avi").string() + ",/no/such.avi",
        " --video " + videos + " --replay " + (dir / "frames").string()}) {
    const auto r = cli::testing::run_minigolf("vision-cam --rig " + rig + to + args);
    EXPECT_EQ(r.exit_code, 2) << args << r.err;
    EXPECT_EQ(cli::testing::count_lines(r.err), 1) << args << r.err;
  }
  // The video plugin (OpenCV's videoio, loaded at run time) not found: one line naming it.
  const auto r = cli::testing::run_command_line(
      "MINIGOLF_VIDEO_PLUGIN=/nonexistent " + std::string(MINIGOLF_BINARY) + " vision-cam --rig " +
      rig + to + " --video " + videos);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(cli::testing::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("video plugin /nonexistent"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("MINIGOLF_VIDEO_PLUGIN"), std::string::npos) << r.err;
}

// No display needed: vision-cam --video with the video plugin not found fails before a frame.
TEST(VisionCli, AMissingVideoPluginIsOneLineNamingIt) {
  const auto r = cli::testing::run_command_line(
      "MINIGOLF_VIDEO_PLUGIN=/nonexistent " + std::string(MINIGOLF_BINARY) + " vision-cam --rig " +
      (data_dir() / "rigs" / "stereo.yaml").string() +
      " --fast --to 127.0.0.1:9 --video a.avi,b.avi");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(cli::testing::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("video plugin /nonexistent"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace mg::vision
