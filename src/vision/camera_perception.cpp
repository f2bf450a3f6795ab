#include "vision/camera_perception.hpp"

#include <chrono>
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
      latency_(renderer.truth(0).latency) {}

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
