#pragma once
/// The control module's eyes in simulator mode with cameras (`--perception camera`): the rig's
/// cameras render the running simulation at the rig's rate in simulated time, the stereo
/// pipeline (vision/stereo_pipeline.hpp) finds ball and hole with the calibration (the robot's
/// belief), and each frame's estimate is released `latency` after its capture. Fresh while the
/// last accepted ball measurement is at most `max_age` old: a ball the cameras lost (occluded
/// by the arm, in the cup) goes stale, and the module holds instead of hitting.
///
/// Not real-time: a capture renders (milliseconds). It is for lockstep simulation, where time is
/// the simulation's; a real rig runs the same pipeline in its own process.
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "sim_backend/simulator_perception.hpp"
#include "system/observe.hpp"
#include "system/system.hpp"
#include "vision/calibration.hpp"
#include "vision/path_observer.hpp"
#include "vision/rig_renderer.hpp"
#include "vision/stereo_pipeline.hpp"

namespace mg::viz {
class GlWindow;
}

namespace mg::vision {

/// What the cameras did over a run.
struct CameraStats {
  long frames = 0;            ///< stereo frames captured
  long ball_stereo = 0;       ///< ... where the ball was triangulated
  long ball_mono = 0;         ///< ... placed from one camera
  long ball_lost = 0;         ///< ... not found (or refused)
  long ball_outliers = 0;     ///< measurements the filter refused
  double cpu_seconds = 0;     ///< detection + triangulation + filter [s, thread CPU]
  double render_seconds = 0;  ///< rendering [s, wall]
};

class CameraPerception final : public perception::Perception {
 public:
  /// Renders the state of `d` (a data of renderer.world()) with `renderer`; the pipeline's model
  /// is `model`. Holds references: all must outlive it. `window` (optional): the OpenGL context
  /// of `renderer`, made current for each capture and released after it (the thread that
  /// renders may change between putts, as Python's threads may hand a SystemData on).
  CameraPerception(RigRenderer& renderer, const StereoModel& model, const mjData* d,
                   viz::GlWindow* window = nullptr);
  perception::Perceived perceive(double now) noexcept override;

  const StereoData& data() const { return data_; }
  /// The pipeline's state, for watching the roll on after the putt (watch_roll).
  StereoData& data() { return data_; }
  const CameraStats& stats() const { return stats_; }
  /// Every stereo frame of the putt (the ball), in capture order.
  const std::vector<PathFrame>& frames() const { return frames_; }
  /// [s] When the next frame would be captured (the world's clock).
  double next_capture() const { return next_capture_; }
  /// [s] The rig's frame period.
  double period() const { return period_; }
  /// The simulation it watches.
  const mjData* data_pointer() const { return d_; }
  /// The last released estimate (ball_in_cup: the ball vanished at the hole).
  const StereoEstimate& estimate() const { return released_; }

 private:
  RigRenderer* renderer_;
  viz::GlWindow* window_;
  const StereoModel* model_;
  const mjData* d_;
  StereoData data_;
  CameraStats stats_;
  std::vector<PathFrame> frames_;
  double period_, latency_;
  double next_capture_ = 0.0;
  bool started_ = false;
  static constexpr int kPending = 64;
  std::array<StereoEstimate, kPending> pending_{};
  std::array<double, kPending> release_{};
  std::array<double, kPending> stamp_{};
  int head_ = 0, count_ = 0;
  StereoEstimate released_;
  double released_stamp_ = -1e300;
};

/// [m] Ball measurements closer than this to where the ball lay are not in a putt's path: the
/// club, right behind the ball for its first centimetres, pulls the ball's blob.
inline constexpr double kClubClearance = 0.07;

/// A PerceptionSource of cameras: one hidden OpenGL window (made here: needs a display, or
/// `xvfb-run -a`), a RigRenderer per world it is attached to, a fresh CameraPerception per putt.
/// It also watches each putt's roll to its end for the learners (system::PathObserver): the
/// module's frames until the hand-off, then the ball-only world rendered at the rig's rate on the
/// same track.
class CameraPerceptionSource final : public perception::PerceptionSource,
                                     public system::PathObserver {
 public:
  /// Throws Error (no display) or InputError (rig).
  CameraPerceptionSource(Rig rig, StereoModel model);
  ~CameraPerceptionSource() override;
  perception::Perception& attach(const sim::World& world, const mjData* d) override;
  /// The last putt's perception (nullptr before the first).
  const CameraPerception* last() const { return perception_.get(); }
  /// The last putt's path as the cameras saw it (see system::PathObserver); its roll after the
  /// hand-off rendered in `system`'s ball-only world from the recorded trajectory.
  std::vector<sim::BallSample> observe_path(const system::System& system,
                                            const control::FullPuttResult& result) override;
  /// What watching the rolls after the hand-off cost, over this source's life.
  const RollStats& roll_stats() const { return roll_stats_; }

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
  Rig rig_;
  StereoModel model_;
  std::unique_ptr<RigRenderer> renderer_;
  std::unique_ptr<CameraPerception> perception_;
  std::unique_ptr<RigRenderer> roll_renderer_;  ///< of the ball-only world
  sim::DataPtr roll_data_;
  RollStats roll_stats_;
};

/// The cameras of a run (`--perception camera [--rig R] [--calibration C]`, Python's
/// `System(perception="camera")`): the rig as it is and the robot's calibration of it.
struct Cameras {
  Rig rig;
  Calibration calibration;
};

/// Loads the rig (file or shipped name) and the calibration (empty: the rig's exact cameras) and
/// checks that they match. Throws InputError/IoError naming the file (one line).
Cameras load_cameras(const std::string& rig, const std::string& calibration);

/// The perception of a System's putts by `cameras` (system::PerceptionFactory): every SystemData
/// gets its own CameraPerceptionSource (its own hidden OpenGL window, made on the thread that
/// makes the data: a display or `xvfb-run -a`), its pipeline's model the calibration on the
/// System's field (the belief). Check check_rig_sees_field first: a source is made only when a
/// thread starts its putts.
system::PerceptionFactory camera_perception(Cameras cameras);

}  // namespace mg::vision
