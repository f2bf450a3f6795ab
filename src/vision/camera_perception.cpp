#include "vision/camera_perception.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

#include "viz/renderer.hpp"

namespace mg::vision {
CameraPerception::CameraPerception(RigRenderer& renderer, const StereoModel& model, const mjData* d,
                                   viz::GlWindow* window)
    : renderer_(&renderer),
      window_(window),
      model_(&model),
      d_(d),
      data_(model),
      period_(1.0 / model.calibration.cameras[0].rate_hz),
      latency_(renderer.truth(0).latency) {
  frames_.reserve(512);
}

perception::Perceived CameraPerception::perceive(double now) noexcept {
  try {
    if (!started_) {
      started_ = true;
      next_capture_ = now;
    }
    // At most one capture per call: the image shows the simulation as it is now.
    if (now >= next_capture_) {
      const auto t0 = std::chrono::steady_clock::now();
      struct Current {  // the context on this thread for the capture only
        viz::GlWindow* w;
        explicit Current(viz::GlWindow* window) : w(window) {
          if (w) w->make_current();
        }
        ~Current() {
          if (w) viz::GlWindow::release_current();
        }
      } current(window_);
      const viz::Image* images[2] = {&renderer_->render(0, d_), &renderer_->render(1, d_)};
      stats_.render_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double c0 = thread_cpu_seconds();
      const long outliers = data_.ball.rejected;
      stereo_frame(*model_, data_, images, now);
      stats_.cpu_seconds += thread_cpu_seconds() - c0;
      frames_.push_back(path_frame(data_, now));
      ++stats_.frames;
      const int views = data_.last_ball.views;
      (views == 2 ? stats_.ball_stereo : views == 1 ? stats_.ball_mono : stats_.ball_lost)++;
      stats_.ball_outliers += data_.ball.rejected - outliers;
      const int slot = (head_ + count_) % kPending;
      if (count_ == kPending) head_ = (head_ + 1) % kPending, --count_;
      pending_[static_cast<std::size_t>(slot)] = stereo_estimate(*model_, data_, now);
      release_[static_cast<std::size_t>(slot)] = now + latency_;
      stamp_[static_cast<std::size_t>(slot)] = now;
      ++count_;
      while (next_capture_ <= now) next_capture_ += period_;
    }
    while (count_ > 0 && release_[static_cast<std::size_t>(head_)] <= now) {
      released_ = pending_[static_cast<std::size_t>(head_)];
      released_stamp_ = stamp_[static_cast<std::size_t>(head_)];
      head_ = (head_ + 1) % kPending;
      --count_;
    }
  } catch (...) {
    // A failed capture is a lost frame: the estimate ages and goes stale.
  }
  perception::Perceived p;
  if (released_stamp_ < -1e299 || !released_.hole_known) return p;
  // Age: from the capture of the last accepted ball measurement to now.
  p.age = (now - released_stamp_) + released_.ball_age;
  p.fresh = released_.ball_fresh && p.age <= model_->config.max_age + latency_;
  for (int i = 0; i < 3; ++i) {
    p.ball[static_cast<std::size_t>(i)] = released_.ball[i];
    p.hole[static_cast<std::size_t>(i)] = released_.hole[i];
  }
  return p;
}

struct CameraPerceptionSource::Gl {
  viz::GlWindow window{64, 64, false, "minigolf cameras"};
};

CameraPerceptionSource::CameraPerceptionSource(Rig rig, StereoModel model)
    : gl_(std::make_unique<Gl>()), rig_(std::move(rig)), model_(std::move(model)) {
  viz::GlWindow::release_current();  // made current by the window; taken for each capture
}

CameraPerceptionSource::~CameraPerceptionSource() {
  gl_->window.make_current();  // the renderers free their GL resources in it
  perception_.reset();
  renderer_.reset();
  roll_renderer_.reset();
  viz::GlWindow::release_current();
}

perception::Perception& CameraPerceptionSource::attach(const sim::World& world, const mjData* d) {
  gl_->window.make_current();
  if (!renderer_ || &renderer_->world() != &world) {
    renderer_.reset();
    renderer_ = std::make_unique<RigRenderer>(world, rig_);
  }
  viz::GlWindow::release_current();
  perception_ = std::make_unique<CameraPerception>(*renderer_, model_, d, &gl_->window);
  return *perception_;
}

std::vector<sim::BallSample> CameraPerceptionSource::observe_path(
    const system::System& system, const control::FullPuttResult& result) {
  if (!perception_ || !result.hit) return {};
  CameraPerception& eyes = *perception_;
  // The contact on the world's clock: the launch was measured a whole number of steps after it.
  const double dt = renderer_->world().model()->opt.timestep;
  const double delay = control::FullPuttOptions{}.launch_delay;
  const double t_contact =
      result.launch_state.time - static_cast<double>(std::lround(delay / dt)) * dt;
  std::vector<PathFrame> frames = eyes.frames();
  // A putt played with another perception (FullPuttOptions::perception_source) left this one's
  // frames from an earlier putt: it did not watch this one.
  if (std::none_of(frames.begin(), frames.end(),
                   [&](const PathFrame& f) { return std::abs(f.stamp - t_contact) <= 0.1; }))
    return {};
  if (result.handed_off && !result.outcome.trajectory.empty()) {
    const sim::World& ball_world = system.ball_world();
    gl_->window.make_current();
    struct Release {
      ~Release() { viz::GlWindow::release_current(); }
    } release;
    if (!roll_renderer_ || &roll_renderer_->world() != &ball_world) {
      roll_renderer_.reset();
      roll_renderer_ = std::make_unique<RigRenderer>(ball_world, rig_);
      roll_data_ = ball_world.make_data();
    }
    // The cup where the module's world had it (the real one, not where the robot believes it).
    const auto hole = renderer_->world().hole_position(eyes.data_pointer());
    const RollStats s = watch_roll(*roll_renderer_, roll_data_.get(), model_, eyes.data(),
                                   result.outcome.trajectory, t_contact, hole, eyes.next_capture(),
                                   eyes.period(), frames);
    roll_stats_.frames += s.frames;
    roll_stats_.lost += s.lost;
    roll_stats_.cpu_seconds += s.cpu_seconds;
    roll_stats_.render_seconds += s.render_seconds;
  }
  // The club follows the ball off the tee; while its head is within a few centimetres, its
  // pixels pull the ball's blob (measured: up to 15 mm off, mostly in height). The robot saw
  // where the ball lay before the club came near: measurements that close to it are not used.
  for (PathFrame& f : frames)
    if (std::hypot(f.point.x() - result.ball_start[0], f.point.y() - result.ball_start[1]) <
        kClubClearance)
      f.accepted = false;
  return path_samples(frames, t_contact);
}

Cameras load_cameras(const std::string& rig, const std::string& calibration) {
  Cameras c{load_rig(rig), {}};
  c.calibration = calibration.empty() ? exact_calibration(c.rig) : load_calibration(calibration);
  check_calibration_matches(c.calibration, c.rig);
  return c;
}

system::PerceptionFactory camera_perception(Cameras cameras) {
  auto shared = std::make_shared<const Cameras>(std::move(cameras));
  return [shared](const system::System& system) -> std::unique_ptr<perception::PerceptionSource> {
    return std::make_unique<CameraPerceptionSource>(
        shared->rig, StereoModel(shared->calibration, system.field()));
  };
}

}  // namespace mg::vision
