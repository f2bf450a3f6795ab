#pragma once
/// Calibrating the rig as a person would: a checkerboard held in front of the cameras in many
/// poses (intrinsics and lens distortion: OpenCV calibrateCamera, refined with the cameras'
/// relative pose by stereoCalibrate), then laid on the lane at a known place (each camera's pose
/// in the field's frame: solvePnP). Images come from RigRenderer (the rig's truth); the result is
/// the robot's belief (vision/calibration.hpp).
#include <cstdint>
#include <string>

#include <mujoco/mujoco.h>

#include "vision/calibration.hpp"
#include "vision/rig_renderer.hpp"

namespace mg::vision {

struct CalibrateOptions {
  int views = 20;             ///< board poses seen by both cameras (at least 15)
  std::uint64_t seed = 1;     ///< board poses
  int cols = 9, rows = 6;     ///< inner corners of the hand-held board
  double square = 0.06;       ///< [m]
  double field_square = 0.1;  ///< [m] the board laid on the lane (same corner counts)
  /// [m] the lane board's corner nearest (x_min, y_min) (x, y); it lies level, rows along x,
  /// 2 mm above the highest point of the surface under it. NaN: centred on the lane.
  double field_x = std::nan(""), field_y = std::nan("");
};

struct CalibrateReport {
  Calibration calibration;
  int poses_tried = 0;     ///< board poses rendered
  int poses_rejected = 0;  ///< ... where a camera did not find every corner or one was 1 px off
  std::vector<double> field_rms_px;  ///< solvePnP's reprojection RMS on the lane board
  double stereo_baseline = 0.0;      ///< [m] |T| of stereoCalibrate
  double pnp_baseline = 0.0;         ///< [m] the same from the two cameras' lane-board poses
  /// The lane board's corners (world) and each camera's detections (the figure).
  Board field_board;
};

/// Renders the boards with `renderer` (the state of `d`, the arm at rest, as background),
/// detects their corners, calibrates. Throws Error (one line) when fewer than 15 poses were
/// found by both cameras or a camera cannot see the lane board.
CalibrateReport calibrate_rig(RigRenderer& renderer, mjData* d, const Rig& rig,
                              const CalibrateOptions& options);

}  // namespace mg::vision
