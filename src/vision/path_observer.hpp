#pragma once
/// The ball's whole roll as the rig saw it, for the learners (system/observe.hpp). The module's
/// cameras (CameraPerception) watch the putt until the hand-off; from there the roll goes on in
/// the ball-only world, which no module looks at. `watch_roll` renders that part: the recorded
/// ball states at the rig's capture times, in the ball-only world (the arm is clear of the ball
/// by then), through the same pipeline and the same track. `path_samples` turns the frames into
/// a path: one sample per accepted measurement, its velocity from the neighbouring ones; a lost
/// ball (hidden, in the cup, refused by the filter) gives no sample, nothing is filled in.
#include <array>
#include <vector>

#include <Eigen/Dense>

#include "sim/putt.hpp"
#include "vision/rig_renderer.hpp"
#include "vision/stereo_pipeline.hpp"

namespace mg::vision {

/// One stereo frame of the ball.
struct PathFrame {
  double stamp = 0.0;     ///< [s] capture time, the world's clock
  int views = 0;          ///< 2: triangulated, 1: from one camera, 0: lost
  bool accepted = false;  ///< the filter took the measurement (no outlier)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< [m] the measurement (views > 0)
};

/// The ball of `data`'s last frame, captured at `stamp`.
PathFrame path_frame(const StereoData& data, double stamp);

/// What watch_roll cost.
struct RollStats {
  long frames = 0;            ///< stereo frames rendered and processed
  long lost = 0;              ///< ... without an accepted ball measurement
  double cpu_seconds = 0.0;   ///< detection + triangulation + filter [s, thread CPU]
  double render_seconds = 0;  ///< rendering [s, wall]
};

/// Renders the ball of `trajectory` (samples in time order, `t` counted from the contact at
/// `t_contact` on the world's clock; positions and velocities interpolated between them by cubic
/// Hermite) in `renderer`'s world (a ball-only world) through `d` (a data of it; its hole set to
/// `hole` here), at the capture times `first`, `first` + `period`, ... while the trajectory
/// lasts; runs the pipeline on each (continuing `data`'s track) and appends a frame to `frames`.
/// Needs the renderer's OpenGL context current.
RollStats watch_roll(RigRenderer& renderer, mjData* d, const StereoModel& model, StereoData& data,
                     const std::vector<sim::BallSample>& trajectory, double t_contact,
                     std::array<double, 2> hole, double first, double period,
                     std::vector<PathFrame>& frames);

/// The ball's path from the frames captured from `t_contact` on: a sample per accepted
/// measurement (`t` from the contact), its position and velocity from a least-squares quadratic
/// in time over the accepted measurements within `half_window` [s] of it (an offline smoother:
/// the robot reads the path after the roll); `vz` along the fit's z. A sample with fewer than 3
/// measurements in its window is left out.
std::vector<sim::BallSample> path_samples(const std::vector<PathFrame>& frames, double t_contact,
                                          double half_window = 0.1);

}  // namespace mg::vision
