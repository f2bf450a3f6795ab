#pragma once
/// The camera rig (data/rigs/*.yaml): where the cameras stand, what they look at, their lenses.
/// A rig file is the truth of the cameras (what the simulator renders); the robot's belief of
/// them is a calibration (vision/calibration.hpp). No OpenCV here.
///
///     format_version: 1
///     name: stereo
///     cameras:
///       - {name: left, position: [x, y, z], look_at: [x, y, z], fovy_deg: 50,
///          width: 640, height: 480, rate_hz: 60,
///          up: [0, 0, 1], distortion: {k1: 0, k2: 0, p1: 0, p2: 0, k3: 0}, latency: 0.0}
///
/// `up`, `distortion` (each coefficient optional) and `latency` are optional. Positions in
/// metres in the field's world frame.
#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "field/field.hpp"

namespace mg::vision {

inline constexpr int kRigFormatVersion = 1;

/// Brown-Conrady lens distortion, OpenCV's order and meaning (normalised image coordinates).
struct Distortion {
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
  std::array<double, 5> coefficients() const { return {k1, k2, p1, p2, k3}; }
};

struct CameraSpec {
  std::string name;
  std::array<double, 3> position{0, 0, 0};  ///< [m] world frame, the optical centre
  std::array<double, 3> look_at{0, 0, 0};   ///< [m] world frame, on the optical axis
  std::array<double, 3> up{0, 0, 1};        ///< world direction shown up in the image
  double fovy_deg = 50.0;                   ///< [deg] vertical field of view
  int width = 640;                          ///< [pixels]
  int height = 480;                         ///< [pixels]
  double rate_hz = 60.0;                    ///< [Hz] frames per second
  Distortion distortion;
  double latency = 0.0;  ///< [s] from exposure to the image being available
};

struct Rig {
  std::string name;
  std::vector<CameraSpec> cameras;  ///< 2..8
  std::string source;               ///< file the rig was read from (named in errors)
};

/// Parses a rig file's text; `source` is named in every error. Throws InputError with one line
/// "SOURCE: KEY.PATH: expected ..., got ..." for unknown keys, missing keys, non-finite or
/// out-of-range values, a camera looking along its `up`, repeated camera names.
Rig parse_rig(std::string_view yaml_text, const std::string& source);
/// Reads a rig file: a path, or the name of a shipped rig ("stereo": data/rigs/stereo.yaml).
/// Throws InputError/IoError.
Rig load_rig(const std::string& name_or_path);
/// The shipped default rig.
inline constexpr const char* kDefaultRig = "stereo";

/// The rig with camera `name` bumped after calibration: moved by `offset` [m, world] and turned
/// by `yaw_deg` about the vertical and `pitch_deg` about its horizontal right axis (its look_at
/// turned about its position). The calibration (the belief) stays the unbumped rig's. Throws
/// InputError for an unknown camera or a turn beyond 10 degrees / a move beyond 0.1 m.
Rig bump_camera(Rig rig, const std::string& name, const std::array<double, 3>& offset,
                double yaw_deg, double pitch_deg);

/// Throws InputError "SOURCE: cameras[i]: camera 'NAME' sees no part of the lane of field F"
/// unless every camera sees some of `field`'s lane surface (a grid of lane points projected
/// through the camera's own lens).
void check_rig_sees_field(const Rig& rig, const field::Field& field);

}  // namespace mg::vision
