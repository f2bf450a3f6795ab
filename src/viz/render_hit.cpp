#include "viz/render_hit.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"

namespace mg::viz {

namespace {

using control::ModuleState;

class HitObserver final : public system::SessionObserver {
 public:
  explicit HitObserver(double fps) : frame_period_(1.0 / fps) {}

  void after_step(const system::SessionView& v) override {
    const mjModel* m = v.world.model();
    const double t = v.d->time;
    if (t >= next_frame_ - 1e-9) {
      frames.push_back(capture_pose(m, v.d));
      next_frame_ += frame_period_;
    }
    const ModuleState state = v.module.state;
    if (state == ModuleState::kHitting && previous_state_ != ModuleState::kHitting && !hit_start) {
      hit_start = t;
      rest = previous_;  // the last step at the rest pose
    }
    if (hit_start && !idle_start &&
        (state == ModuleState::kHitting || state == ModuleState::kBraking))
      hit_poses.push_back(capture_pose(m, v.d));
    if (hit_start && v.module.ball_hit && !impact) {  // the module saw the hit (measured)
      impact = capture_pose(m, v.d);
    }
    if (state == ModuleState::kBraking && previous_state_ != ModuleState::kBraking &&
        !braking_start)
      braking_start = t;
    if (state == ModuleState::kIdle && previous_state_ == ModuleState::kBraking && !idle_start)
      idle_start = t;
    if (idle_start && !idle && t >= *idle_start + 0.3) idle = capture_pose(m, v.d);
    if (impact && t >= next_path_) {
      const mjtNum* b = v.d->qpos + v.world.ids().ball_qpos;
      if (v.ball_rolling || ball_path.empty()) {
        ball_path.push_back({b[0], b[1], b[2]});
        ball_path_time.push_back(t);
      }
      next_path_ = t + 0.01;
    }
    previous_state_ = state;
    // The previous step's pose, reusing the vectors' memory.
    previous_.time = t;
    previous_.qpos.assign(v.d->qpos, v.d->qpos + m->nq);
    previous_.mocap_pos.assign(v.d->mocap_pos, v.d->mocap_pos + 3 * m->nmocap);
    previous_.mocap_quat.assign(v.d->mocap_quat, v.d->mocap_quat + 4 * m->nmocap);
    previous_.userdata.assign(v.d->userdata, v.d->userdata + m->nuserdata);
  }

  std::vector<Pose> frames, hit_poses;
  std::optional<Pose> rest, impact, idle;
  std::optional<double> hit_start, braking_start, idle_start;
  std::vector<std::array<double, 3>> ball_path;
  std::vector<double> ball_path_time;

 private:
  double frame_period_;
  double next_frame_ = 0.0;
  double next_path_ = 0.0;
  ModuleState previous_state_ = ModuleState::kIdle;
  Pose previous_;
};

const Pose& nearest(const std::vector<Pose>& poses, double t) {
  std::size_t best = 0;
  for (std::size_t k = 0; k < poses.size(); ++k)
    if (std::abs(poses[k].time - t) < std::abs(poses[best].time - t)) best = k;
  return poses[best];
}

/// The session's new output since `from`; InputError for a refusal or an error line.
void check_answer(const std::string& log, std::size_t from, const std::string& line) {
  std::istringstream in(log.substr(from));
  std::string text;
  while (std::getline(in, text))
    if (text.find("refused") != std::string::npos || text.rfind("error:", 0) == 0)
      throw InputError(fmt::format("render: '{}': {}", line, text));
}

}  // namespace

void validate(const HitRequest& request) {
  if (!(request.fps >= 1.0 && request.fps <= 240.0))
    throw InputError(fmt::format("render: --fps {}: expected 1..240", request.fps));
  const bool manual = request.angle.has_value() || request.speed.has_value();
  if (manual == !request.params_model.empty())
    throw InputError("render: give either --angle and --speed, or --model");
  if (manual && !(request.angle && request.speed))
    throw InputError("render: --angle and --speed go together");
}

HitRecording record_hit(const control::ModuleConfig& config, const HitRequest& request,
                        bool record_poses) {
  validate(request);
  const bool manual = request.angle.has_value() || request.speed.has_value();
  HitObserver observer(request.fps);
  std::ostringstream out;
  system::SessionOptions options;
  options.observer = record_poses ? &observer : nullptr;
  HitRecording rec;
  {
    system::Session session(config, options, out);
    std::vector<std::string> script;
    if (request.hole)
      script.push_back(fmt::format("hole {} {}", format_exact((*request.hole)[0]),
                                   format_exact((*request.hole)[1])));
    if (manual) {
      script.push_back("angle " + format_exact(*request.angle));
      script.push_back("speed " + format_exact(*request.speed));
    } else {
      script.push_back("load params " + request.params_model);
      script.push_back("wait 0.02");  // a robot update: fresh perception for `auto`
      script.push_back("auto");
    }
    script.push_back("hit");
    for (const auto& line : script) {
      const std::size_t from = out.str().size();
      session.execute(line);
      check_answer(out.str(), from, line);
    }
    double decided_at = -1.0;
    for (double waited = 0.0; waited < request.max_time; waited += 0.1) {
      session.execute("wait 0.1");
      bool done = false;
      session.inspect([&](const system::SessionView& v) {
        if (v.last_outcome && decided_at < 0) decided_at = v.d->time;
        done = decided_at >= 0 && v.module.state == ModuleState::kIdle &&
               v.d->time >= decided_at + request.after_outcome;
        if (done || waited + 0.1 >= request.max_time) {
          if (v.last_outcome) rec.outcome = *v.last_outcome;
          rec.hole = v.world.hole_position(v.d);
          rec.angle = v.angle;
          rec.speed = v.speed;
        }
      });
      if (done) break;
    }
    session.execute("quit");
  }
  rec.log = out.str();
  if (!rec.outcome)
    throw Error(
        fmt::format("render: no ball outcome within {} s of simulated time", request.max_time));
  if (!record_poses) return rec;
  rec.frames = std::move(observer.frames);
  rec.ball_path = std::move(observer.ball_path);
  rec.ball_path_time = std::move(observer.ball_path_time);
  const auto& o = observer;
  if (o.rest) rec.stages.push_back({"rest", *o.rest});
  if (o.hit_start && o.impact && !o.hit_poses.empty())
    rec.stages.push_back(
        {"acceleration", nearest(o.hit_poses, 0.5 * (*o.hit_start + o.impact->time))});
  if (o.impact) rec.stages.push_back({"impact", *o.impact});
  if (o.braking_start && o.idle_start && !o.hit_poses.empty())
    rec.stages.push_back(
        {"braking", nearest(o.hit_poses, 0.5 * (*o.braking_start + *o.idle_start))});
  if (o.idle) rec.stages.push_back({"idle", *o.idle});
  return rec;
}

void check_render_outputs(const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw IoError(fmt::format("render: -o {}: no folder {}", out.string(), dir.string()));
  for (const std::string suffix : {".mp4", "-filmstrip.png"}) {
    const fs::path p = out.string() + suffix;
    if (fs::exists(fs::symlink_status(p, ec)) && !fs::is_regular_file(fs::symlink_status(p, ec)))
      throw IoError(fmt::format("render: {} exists and is not a regular file", p.string()));
  }
}

std::filesystem::path find_ffmpeg() {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::string dirs = path;
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::filesystem::path candidate =
        std::filesystem::path(dirs.substr(start, end - start)) / "ffmpeg";
    if (!candidate.parent_path().empty() && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    start = end + 1;
  }
  return {};
}

VideoOutput write_video(const std::filesystem::path& out, int width, int height, double fps,
                        int count, const std::function<Image(int)>& frame) {
  const auto checked = [&](int k) {
    Image img = frame(k);
    if (img.width != width || img.height != height)
      throw Error(fmt::format("video: frame {} is {}x{}, expected {}x{}", k, img.width, img.height,
                              width, height));
    return img;
  };
  VideoOutput result;
  const std::string stem = out.string();
  const std::filesystem::path ffmpeg = find_ffmpeg();
  if (ffmpeg.empty()) {
    result.path = stem + "-frames";
    std::filesystem::create_directories(result.path);
    for (int k = 0; k < count; ++k) {
      write_png(result.path / fmt::format("frame-{:05d}.png", k), checked(k));
      ++result.frames;
    }
    return result;
  }
  result.path = stem + ".mp4";
  const std::string tmp = stem + ".tmp.mp4";
  const std::string cmd = fmt::format(
      "{} -loglevel error -y -f rawvideo -pix_fmt rgb24 -s {}x{} -r {} -i - -an -c:v libx264 "
      "-pix_fmt yuv420p -movflags +faststart -f mp4 {}",
      shell_quote(ffmpeg.string()), width, height, fps, shell_quote(tmp));
  FILE* pipe = ::popen(cmd.c_str(), "w");
  if (!pipe) throw IoError("render: cannot start ffmpeg");
  bool ok = true;
  try {
    for (int k = 0; k < count; ++k) {
      const Image img = checked(k);
      if (std::fwrite(img.rgb.data(), 1, img.rgb.size(), pipe) != img.rgb.size()) {
        ok = false;
        break;
      }
      ++result.frames;
    }
  } catch (...) {
    ::pclose(pipe);
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  const int status = ::pclose(pipe);
  if (!ok || status != 0) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw IoError(fmt::format("render: ffmpeg failed writing {} (exit status {})",
                              result.path.string(), status));
  }
  std::filesystem::rename(tmp, result.path);
  result.used_ffmpeg = true;
  return result;
}

RenderOutputs render_hit(const sim::World& world, const HitRecording& rec,
                         const RenderOptions& options, const std::filesystem::path& out) {
  if (options.width % 2 != 0 || options.height % 2 != 0)
    throw InputError(fmt::format("render: --size {}x{}: width and height must be even (video)",
                                 options.width, options.height));
  if (rec.frames.empty() || rec.stages.empty()) throw Error("render: nothing recorded");
  check_render_outputs(out);
  Renderer renderer(world, options.width, options.height);
  renderer.set_pose(rec.stages.front().pose);  // the run's hole, for the camera
  mjvCamera camera = camera_preset(options.camera, world, renderer.data());
  RenderOutputs result;
  const std::string stem = out.string();
  result.filmstrip = stem + "-filmstrip.png";

  Decorations deco;
  const auto path_until = [&](double t) {
    std::vector<std::array<double, 3>> p;
    for (std::size_t k = 0; k < rec.ball_path.size(); ++k)
      if (rec.ball_path_time[k] <= t) p.push_back(rec.ball_path[k]);
    return p;
  };

  std::vector<Image> stills;
  for (const auto& stage : rec.stages) {
    renderer.set_pose(stage.pose);
    if (options.camera == "follow") camera = camera_preset(options.camera, world, renderer.data());
    deco.label = fmt::format("{}  t={:.2f} s", stage.name, stage.pose.time);
    deco.aim_angle = stage.name == "rest" ? std::optional<double>(rec.angle) : std::nullopt;
    deco.path = path_until(stage.pose.time);
    stills.push_back(renderer.render(camera, deco));
  }
  write_png(result.filmstrip, filmstrip(stills));

  if (!options.video) return result;
  deco.aim_angle.reset();
  const VideoOutput video =
      write_video(out, options.width, options.height, options.fps,
                  static_cast<int>(rec.frames.size()), [&](int k) {
                    const Pose& pose = rec.frames[static_cast<std::size_t>(k)];
                    renderer.set_pose(pose);
                    if (options.camera == "follow")
                      camera = camera_preset(options.camera, world, renderer.data());
                    deco.label = fmt::format("t={:.2f} s  angle {:.3f} rad  speed {:.2f} m/s",
                                             pose.time, rec.angle, rec.speed);
                    deco.path = path_until(pose.time);
                    return renderer.render(camera, deco);
                  });
  result.video = video.path;
  result.frames = video.frames;
  result.used_ffmpeg = video.used_ffmpeg;
  return result;
}

}  // namespace mg::viz
