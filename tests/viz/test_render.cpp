// Rendered hits: the recording observer leaves the simulation's bits alone; off-screen images
// have the requested size, change between rest and impact, and show the ball where the
// simulation has it (its centre projected with the scene's camera lands on white ball pixels).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "core/error.hpp"
#include "system/system.hpp"
#include "viz/render_hit.hpp"
#include "viz/renderer.hpp"
#include "viz_test_util.hpp"

namespace mg::viz {
namespace {

HitRequest straight_hit() {
  HitRequest r;
  r.angle = 0.0;
  r.speed = 0.8;
  r.fps = 10.0;
  return r;
}

control::ModuleConfig flat() { return system::load_config("", "flat"); }

TEST(RecordHit, RecordingDoesNotChangeTheSimulation) {
  const HitRecording with = record_hit(flat(), straight_hit(), true);
  const HitRecording without = record_hit(flat(), straight_hit(), false);
  ASSERT_TRUE(with.outcome && without.outcome);
  EXPECT_EQ(std::memcmp(with.outcome->rest_position.data(), without.outcome->rest_position.data(),
                        sizeof(double) * 2),
            0);
  EXPECT_EQ(with.outcome->duration, without.outcome->duration);
  EXPECT_EQ(with.log, without.log);  // every transition and the outcome line, to the printed digit
  // All five stages, in time order, with the impact after the ball was last at rest.
  ASSERT_EQ(with.stages.size(), 5u) << with.log;
  const char* names[] = {"rest", "acceleration", "impact", "braking", "idle"};
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(with.stages[k].name, names[k]);
    if (k > 0) {
      EXPECT_GT(with.stages[k].pose.time, with.stages[k - 1].pose.time);
    }
  }
  EXPECT_GT(with.frames.size(), 20u);  // 10 fps over the rest approach, the hit and the roll
  EXPECT_GT(with.ball_path.size(), 10u);
  // The ball rolled along +x from the tee (angle 0).
  EXPECT_GT(with.outcome->rest_position[0], 0.3);
  EXPECT_NEAR(with.outcome->rest_position[1], 0.0, 0.03);
}

TEST(RecordHit, BadRequestsAreInputErrors) {
  HitRequest r = straight_hit();
  r.angle = 3.0;  // outside the safe envelope
  EXPECT_THROW(record_hit(flat(), r), InputError);
  r = straight_hit();
  r.params_model = "data/models/missing.json";
  EXPECT_THROW(record_hit(flat(), r), InputError);  // both --angle/--speed and --model
  r = straight_hit();
  r.speed.reset();
  EXPECT_THROW(record_hit(flat(), r), InputError);
  r = straight_hit();
  r.fps = 0.0;
  EXPECT_THROW(record_hit(flat(), r), InputError);
}

/// True when a pixel within `radius` of (u, v) is ball-white (every channel bright).
bool white_near(const Image& img, double u, double v, int radius) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int x = static_cast<int>(std::lround(u)) + dx,
                y = static_cast<int>(std::lround(v)) + dy;
      if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
      const auto* p = img.pixel(x, y);
      if (p[0] > 170 && p[1] > 170 && p[2] > 170) return true;
    }
  return false;
}

/// Centroid of the ball-white pixels within `radius` of (u, v); nullopt if there are none.
std::optional<std::array<double, 2>> white_centroid(const Image& img, double u, double v,
                                                    int radius) {
  double su = 0, sv = 0;
  int n = 0;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int x = static_cast<int>(std::lround(u)) + dx,
                y = static_cast<int>(std::lround(v)) + dy;
      if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
      const auto* p = img.pixel(x, y);
      if (p[0] > 170 && p[1] > 170 && p[2] > 170) su += x + 0.5, sv += y + 0.5, ++n;
    }
  if (n == 0) return std::nullopt;
  return std::array<double, 2>{su / n, sv / n};
}

std::array<double, 3> ball_of(const sim::World& world, const Pose& pose) {
  const auto i = static_cast<std::size_t>(world.ids().ball_qpos);
  return {pose.qpos[i], pose.qpos[i + 1], pose.qpos[i + 2]};
}

TEST(RenderDisplay, OffscreenImagesShowTheBallWhereTheSimulationHasIt) {
  MG_NEED_DISPLAY();
  const HitRecording rec = record_hit(flat(), straight_hit());
  ASSERT_EQ(rec.stages.size(), 5u);
  const system::System sys(flat());
  const sim::World& world = sys.arm_world();
  GlWindow window(64, 64, false, "test");
  Renderer r(world, 320, 240);

  r.set_pose(rec.stages[0].pose);  // rest
  mjvCamera side = camera_preset("side", world, r.data());
  const Image rest = r.render(side, {});
  EXPECT_EQ(rest.width, 320);
  EXPECT_EQ(rest.height, 240);
  const auto ball = ball_of(world, rec.stages[0].pose);
  const auto at = r.project(ball);
  ASSERT_TRUE(at);
  ASSERT_GT((*at)[0], 0);
  ASSERT_LT((*at)[0], 320);
  EXPECT_TRUE(white_near(rest, (*at)[0], (*at)[1], 1))
      << "ball at pixel " << (*at)[0] << "," << (*at)[1];
  // The white blob around it is centred on the projection (the ball is about 6 pixels across).
  const auto blob = white_centroid(rest, (*at)[0], (*at)[1], 8);
  ASSERT_TRUE(blob);
  const double offset = std::hypot((*blob)[0] - (*at)[0], (*blob)[1] - (*at)[1]);
  std::printf("ball: projected (%.2f, %.2f), white blob centroid (%.2f, %.2f): %.2f px apart\n",
              (*at)[0], (*at)[1], (*blob)[0], (*blob)[1], offset);
  EXPECT_LT(offset, 1.5) << "blob " << (*blob)[0] << "," << (*blob)[1] << " projection " << (*at)[0]
                         << "," << (*at)[1];
  // 15 cm beside the ball there is lane, not ball: the check can fail.
  const auto off = r.project({ball[0], ball[1] - 0.15, ball[2]});
  ASSERT_TRUE(off);
  EXPECT_FALSE(white_near(rest, (*off)[0], (*off)[1], 1));

  r.set_pose(rec.stages[2].pose);  // impact: the club is at the ball
  const Image impact = r.render(side, {});
  EXPECT_GT(mean_abs_difference(rest, impact), 1.0);

  // Idle, seen from above at 640x480: the ball has rolled away; it is where the simulation says.
  Renderer big(world, 640, 480);
  big.set_pose(rec.stages[4].pose);
  mjvCamera top = camera_preset("top", world, big.data());
  const Image idle = big.render(top, {});
  EXPECT_EQ(idle.width, 640);
  const auto rolled = ball_of(world, rec.stages[4].pose);
  ASSERT_GT(std::hypot(rolled[0] - ball[0], rolled[1] - ball[1]), 0.2);
  const auto at2 = big.project(rolled);
  ASSERT_TRUE(at2);
  EXPECT_TRUE(white_near(idle, (*at2)[0], (*at2)[1], 1)) << (*at2)[0] << "," << (*at2)[1];
  const auto tee = big.project(ball);
  ASSERT_TRUE(tee);
  EXPECT_FALSE(white_near(idle, (*tee)[0], (*tee)[1], 0));  // the tee is empty now
}

TEST(RenderDisplay, RenderHitWritesAVideoAndAFilmstrip) {
  MG_NEED_DISPLAY();
  const HitRecording rec = record_hit(flat(), straight_hit());
  const system::System sys(flat());
  GlWindow window(64, 64, false, "test");
  RenderOptions o;
  o.width = 160;
  o.height = 120;
  o.fps = 10.0;
  const auto dir = testing::temp_dir("render");
  const RenderOutputs out = render_hit(sys.arm_world(), rec, o, dir / "hit");
  const Image strip = read_png(out.filmstrip);
  EXPECT_EQ(strip.height, 120);
  EXPECT_EQ(strip.width, 5 * 160 + 4 * 4);
  EXPECT_EQ(out.frames, static_cast<int>(rec.frames.size()));
  ASSERT_TRUE(std::filesystem::exists(out.video));
  if (out.used_ffmpeg) {
    EXPECT_GT(std::filesystem::file_size(out.video), 1000u);
    // The MP4 holds every frame at the requested size (ffprobe, from the same Debian package,
    // decodes it).
    const std::string probe =
        "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
        "stream=width,height,nb_read_frames -of csv=p=0 '" +
        out.video.string() + "' 2>&1";
    FILE* pipe = ::popen(probe.c_str(), "r");
    ASSERT_TRUE(pipe);
    char buf[256] = {};
    const bool got = std::fgets(buf, sizeof buf, pipe) != nullptr;
    const int status = ::pclose(pipe);
    ASSERT_TRUE(got && status == 0) << buf;
    EXPECT_EQ(std::string(buf), "160,120," + std::to_string(out.frames) + "\n");
  }
}

}  // namespace
}  // namespace mg::viz
