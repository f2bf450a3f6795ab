#pragma once
/// The rig's cameras rendered from the true world (MuJoCo, off-screen): the arm, the club and the
/// ball as they are, the cup's opening as the dark disc a camera sees, lens distortion applied.
/// Needs a current OpenGL context (viz::GlWindow; `xvfb-run -a` without a screen).
#include <memory>
#include <vector>

#include <mujoco/mujoco.h>
#include <Eigen/Dense>

#include "sim/world.hpp"
#include "vision/camera_model.hpp"
#include "vision/rig.hpp"
#include "viz/image.hpp"

namespace mg::vision {

/// A calibration checkerboard: `cols` x `rows` inner corners, `square` [m]; corner (i, j) at
/// origin + R (i square, j square, 0), on the face seen from -z. The square diagonal before
/// corner (0, 0) is black, the one after the last corner white (so the corner order is never
/// ambiguous).
struct Board {
  int cols = 9, rows = 6;
  double square = 0.06;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();   ///< board -> world
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< [m] world, corner (0, 0)
  Eigen::Vector3d corner(int i, int j) const {
    return origin + R * Eigen::Vector3d(i * square, j * square, 0.0);
  }
};

class RigRenderer {
 public:
  /// One off-screen renderer per camera of `rig` (the truth), drawing `world`'s state. Needs a
  /// current OpenGL context; throws Error/InputError as viz::Renderer.
  RigRenderer(const sim::World& world, const Rig& rig);
  ~RigRenderer();
  RigRenderer(const RigRenderer&) = delete;
  RigRenderer& operator=(const RigRenderer&) = delete;

  int size() const;
  const CameraModel& truth(int camera) const;
  const sim::World& world() const;
  /// Camera `camera`'s image of the state in `d` (a data of world()), with `board` in the scene
  /// when given. The image is owned by the renderer (valid until the next call for this camera).
  const viz::Image& render(int camera, const mjData* d, const Board* board = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mg::vision
