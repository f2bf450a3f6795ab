#pragma once
/// The robot's belief of its cameras: a calibration file (written by `minigolf vision
/// calibrate`, read by the camera pipeline). YAML, format_version 1; strict like every data file
/// (unknown keys, non-finite or out-of-range values: one line naming the file and key).
#include <string>
#include <string_view>
#include <vector>

#include "vision/camera_model.hpp"
#include "vision/rig.hpp"

namespace mg::vision {

inline constexpr int kCalibrationFormatVersion = 1;

struct Calibration {
  std::string rig;                   ///< the rig's name
  std::vector<CameraModel> cameras;  ///< in the rig's order
  std::vector<double> rms_px;        ///< per camera: calibrateCamera's reprojection RMS [pixels]
  double stereo_rms_px = 0.0;        ///< stereoCalibrate's RMS of the first two cameras [pixels]
  int views = 0;                     ///< board poses used
  std::string source;
};

/// The rig's own cameras, exactly (a calibration that knows the truth: tests, `--calibration
/// truth`).
Calibration exact_calibration(const Rig& rig);

std::string format_calibration(const Calibration& calibration);
/// Throws InputError naming `source` and the key.
Calibration parse_calibration(std::string_view yaml_text, const std::string& source);
Calibration load_calibration(const std::string& path);
/// Throws InputError unless the calibration has the rig's cameras (names and image sizes).
void check_calibration_matches(const Calibration& calibration, const Rig& rig);

}  // namespace mg::vision
