#pragma once
/// One still scene seen by the rig: the arm at its default rest posture beside the tee, the ball
/// at rest where asked, the hole where asked; what the cameras locate against the truth.
/// (`minigolf vision measure`, the static-error figures, the tests.)
#include <array>
#include <vector>

#include <mujoco/mujoco.h>
#include <Eigen/Dense>

#include "vision/rig_renderer.hpp"
#include "vision/stereo_pipeline.hpp"

namespace mg::vision {

/// Resets `d` (a data of `world`, with the arm) to the scene and runs mj_forward.
void place_still_scene(const sim::World& world, mjData* d, std::array<double, 2> ball,
                       std::array<double, 2> hole);

struct StillMeasurement {
  Sighting ball, hole;
  Eigen::Vector3d true_ball = Eigen::Vector3d::Zero();  ///< [m] centre
  Eigen::Vector3d true_hole = Eigen::Vector3d::Zero();  ///< [m] on the surface
  double cpu_seconds = 0.0;        ///< detection + triangulation of ball and hole (no rendering)
  double render_seconds = 0.0;     ///< wall time of rendering the cameras
  std::vector<viz::Image> images;  ///< the first two cameras' frames
};

/// Renders the state of `d` with every camera and locates ball and hole (no memory: a fresh
/// look, as the first frame of a run).
StillMeasurement measure_still(RigRenderer& renderer, const StereoModel& model, StereoData& data,
                               const mjData* d);

/// The frame with its detections drawn: a ring of the blob's radius + 3 pixels (ball: red, hole:
/// blue) and, when given, the truth projected as a small green cross.
viz::Image annotate(const viz::Image& image, const Blob& ball, const Blob& hole,
                    const std::vector<Eigen::Vector2d>& truth = {});

}  // namespace mg::vision
