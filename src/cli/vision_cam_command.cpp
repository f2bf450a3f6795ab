// vision-cam: the stereo-vision computer as its own process (docs/perception.md "Cameras").
//
//   minigolf vision-cam [--rig R] [--calibration C] [--to HOST:PORT] [--field F] [--hole X,Y]
//                       [--angle RAD --speed M/S] [--duration S]
//                       [--frames DIR | --replay DIR | --video LEFT,RIGHT] [--fast]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <thread>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "perception/udp.hpp"
#include "perception/vision_message.hpp"
#include "sim/putt.hpp"
#include "system/system.hpp"
#include "vision/calibrate.hpp"
#include "vision/calibration.hpp"
#include "vision/rig.hpp"
#include "vision/still_scene.hpp"
#include "vision/video.hpp"
#include "viz/renderer.hpp"

namespace mg::cli {

void add_vision_cam_command(CLI::App& app) {
  struct CamOptions {
    std::string rig = vision::kDefaultRig;
    std::string calibration;
    std::string to = "127.0.0.1:47001";
    std::string field = "flat";
    std::string hole;
    double angle = 0.0, speed = 0.0, duration = 2.0;
    std::string frames, replay;
    std::vector<std::string> videos;
    bool fast = false;
  };
  auto v = std::make_shared<CamOptions>();
  CLI::App* cam = app.add_subcommand(
      "vision-cam",
      "The stereo-vision computer: cameras (rendered, or recorded PNG pairs) -> ball and hole -> "
      "minigolf-vision/1 datagrams at the rig's rate");
  cam->add_option("--rig", v->rig, "Rig file or shipped rig name")->capture_default_str();
  cam->add_option("--calibration", v->calibration,
                  "Calibration file (vision calibrate); default: the rig's exact cameras");
  cam->add_option("--to", v->to, "Destination HOST:PORT")->capture_default_str();
  cam->add_option("--field", v->field, "Shipped field name or path to a field file")
      ->capture_default_str();
  cam->add_option("--hole", v->hole, "Hole centre X,Y [m] (default: the field's)");
  CLI::Option* angle_opt =
      cam->add_option("--angle", v->angle, "Putt angle [rad]: a rolling ball (needs --speed)")
          ->check(finite_number(-3.15, 3.15));
  CLI::Option* speed_opt =
      cam->add_option("--speed", v->speed, "Putt speed [m/s]: a rolling ball (needs --angle)")
          ->check(finite_number(1e-3, 15.0));
  cam->add_option("--duration", v->duration, "Seconds of capture, (0, 600]")
      ->check(finite_number(1e-3, 600.0))
      ->capture_default_str();
  cam->add_option("--frames", v->frames,
                  "Write every captured pair as FRAMES/frame-NNNNN-CAMERA.png (rendered only)");
  cam->add_option("--replay", v->replay,
                  "Read the pairs from this folder (frame-NNNNN-CAMERA.png, as --frames writes "
                  "them; a real rig's footage) instead of rendering; no display needed");
  add_list_option(cam, "--video", v->videos,
                  "Read the pairs from two video files, the rig's first and second camera's "
                  "footage (LEFT,RIGHT; what OpenCV's FFmpeg reads: MJPG AVI, MP4, ...) instead "
                  "of rendering; no display needed",
                  any_name());
  cam->add_flag("--fast", v->fast, "No pacing (tests)");
  cam->callback([v, angle_opt, speed_opt] {
    const auto [host, port] = perception::parse_host_port("--to", v->to);
    if ((angle_opt->count() == 0) != (speed_opt->count() == 0))
      throw InputError("vision-cam: --angle and --speed go together (a rolling ball)");
    if (!v->replay.empty() && (angle_opt->count() > 0 || !v->frames.empty()))
      throw InputError("vision-cam: --replay reads recorded frames (not with --angle, --frames)");
    if (!v->videos.empty() && (angle_opt->count() > 0 || !v->frames.empty() || !v->replay.empty()))
      throw InputError(
          "vision-cam: --video reads recorded footage (not with --angle, --frames, --replay)");
    if (!v->videos.empty() && v->videos.size() != 2)
      throw InputError(fmt::format(
          "--video: expected two files (the first and second camera's), got {}", v->videos.size()));
    const vision::Rig rig = vision::load_rig(v->rig);
    const system::System sys(system::load_config("", v->field));
    const sim::World& world = sys.ball_world();
    const field::Field& f = world.field();
    vision::check_rig_sees_field(rig, f);
    vision::Calibration calib = v->calibration.empty() ? vision::exact_calibration(rig)
                                                       : vision::load_calibration(v->calibration);
    vision::check_calibration_matches(calib, rig);
    const auto hole = v->hole.empty() ? f.hole.position : parse_vector<2>("--hole", v->hole);
    field::check_hole_position(f, hole);
    const vision::StereoModel model(calib, sys.field());
    vision::StereoData data(model);
    perception::UdpSender sender(host, port);
    const double period = 1.0 / rig.cameras[0].rate_hz, latency = rig.cameras[0].latency;
    const auto name = [&](int k, int i) {
      return fmt::format("frame-{:05d}-{}.png", k, rig.cameras[static_cast<std::size_t>(i)].name);
    };
    std::vector<std::unique_ptr<vision::VideoReader>> videos;
    for (const auto& file : v->videos)
      videos.push_back(std::make_unique<vision::VideoReader>(file));
    const bool recorded = !v->replay.empty() || !videos.empty();
    std::unique_ptr<viz::GlWindow> window;
    std::unique_ptr<vision::RigRenderer> renderer;
    sim::DataPtr d;
    std::filesystem::path out_dir;
    const bool moving = speed_opt->count() > 0;
    if (!recorded) {
      window = std::make_unique<viz::GlWindow>(64, 64, false, "minigolf vision-cam");
      renderer = std::make_unique<vision::RigRenderer>(world, rig);
      d = world.make_data();
      if (!v->frames.empty()) out_dir = frames_dir(v->frames);
      if (moving) {
        sim::PuttRequest req;
        req.angle = v->angle;
        req.speed = v->speed;
        sim::start_putt(world, d.get(), hole, req);
      } else {
        world.reset(d.get());
        world.set_hole(d.get(), hole);
        sim::BallState b = world.ball_state(d.get());
        b.qpos = {f.tee[0], f.tee[1], f.height(f.tee[0], f.tee[1]) + f.ball.radius, 1, 0, 0, 0};
        world.set_ball_state(d.get(), b);
        mj_forward(world.model(), d.get());
      }
    }
    const std::uint64_t count =
        std::max<std::uint64_t>(1, static_cast<std::uint64_t>(v->duration / period + 1e-9));
    std::uint64_t sent = 0, stale = 0, failed = 0, frames = 0;
    std::vector<viz::Image> replayed(2);
    const auto start = std::chrono::steady_clock::now();
    const double t0 = d ? d->time : 0.0;
    for (std::uint64_t k = 0; k < count; ++k) {
      const double t = static_cast<double>(k) * period;  // capture time [s]
      const viz::Image* images[2];
      if (!videos.empty()) {
        bool ended = false;
        for (int i = 0; i < 2; ++i) {
          auto& image = replayed[static_cast<std::size_t>(i)];
          if (!videos[static_cast<std::size_t>(i)]->read(image)) {
            ended = true;  // the shorter footage ends the run
            break;
          }
          const auto& cm = calib.cameras[static_cast<std::size_t>(i)];
          if (image.width != cm.width || image.height != cm.height)
            throw InputError(
                fmt::format("--video: {}: expected {}x{} pixels (camera '{}'), got {}x{}",
                            videos[static_cast<std::size_t>(i)]->path(), cm.width, cm.height,
                            cm.name, image.width, image.height));
          images[i] = &image;
        }
        if (ended) break;
      } else if (!v->replay.empty()) {
        const std::filesystem::path dir(v->replay);
        if (!std::filesystem::exists(dir / name(static_cast<int>(k), 0))) break;  // footage ends
        for (int i = 0; i < 2; ++i) {
          replayed[static_cast<std::size_t>(i)] = viz::read_png(dir / name(static_cast<int>(k), i));
          const auto& cm = calib.cameras[static_cast<std::size_t>(i)];
          if (replayed[static_cast<std::size_t>(i)].width != cm.width ||
              replayed[static_cast<std::size_t>(i)].height != cm.height)
            throw InputError(fmt::format("--replay: {}: expected {}x{} pixels (camera '{}')",
                                         (dir / name(static_cast<int>(k), i)).string(), cm.width,
                                         cm.height, cm.name));
          images[i] = &replayed[static_cast<std::size_t>(i)];
        }
      } else {
        while (moving && d->time - t0 < t - 1e-12) world.step(d.get());
        for (int i = 0; i < 2; ++i) {
          images[i] = &renderer->render(i, d.get());
          if (!out_dir.empty()) viz::write_png(out_dir / name(static_cast<int>(k), i), *images[i]);
        }
      }
      ++frames;
      vision::stereo_frame(model, data, images, t);
      const vision::StereoEstimate e = vision::stereo_estimate(model, data, t);
      if (!e.ball_fresh || !e.hole_known) {
        ++stale;  // nothing fresh to say: a receiver's feed goes stale, as it should
        continue;
      }
      perception::VisionMessage m;
      m.seq = k + 1;
      m.stamp = t;
      for (int i = 0; i < 3; ++i) {
        m.ball[static_cast<std::size_t>(i)] = e.ball[i];
        m.hole[static_cast<std::size_t>(i)] = e.hole[i];
      }
      if (!v->fast)
        std::this_thread::sleep_until(
            start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                        std::chrono::duration<double>(t + latency)));
      (sender.send(perception::format_vision_message(m)) ? sent : failed)++;
    }
    fmt::print(
        "vision-cam: sent {} to {}:{} from {} stereo frames ({}; {} without a fresh ball), send "
        "errors {}\n",
        sent, host, port, frames,
        !videos.empty()      ? "videos " + fmt::format("{}", fmt::join(v->videos, ","))
        : !v->replay.empty() ? "replayed " + v->replay
        : moving             ? "rolling ball"
                             : "ball at rest",
        stale, failed);
  });
}

}  // namespace mg::cli
