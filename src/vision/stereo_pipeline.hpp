#pragma once
/// From a set of simultaneous images to the ball and the hole: detection in every image,
/// undistortion and triangulation with the calibration (the robot's belief of its cameras), a
/// reprojection-error gate, a plausibility gate (on the lane, at the surface), the ball's
/// filter, and the hole's running mean. A ball lost by one camera is placed from the other on
/// the (believed) surface; lost by all, the filter predicts, and the estimate goes stale.
///
/// Model/data: `StereoModel` (calibration, field, config; immutable, shared) and `StereoData`
/// (detectors, track; one per run). `stereo_frame` allocates only on the first frame of an image
/// size (OpenCV's buffers), not on the next ones.
#include <array>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "field/field.hpp"
#include "vision/calibration.hpp"
#include "vision/detect.hpp"
#include "vision/tracker.hpp"

namespace mg::vision {

struct StereoConfig {
  DetectorConfig detector;
  TrackerConfig tracker;
  double gate_px = 2.0;         ///< [pixels] largest accepted reprojection error of a triangulation
  double surface_tol = 0.03;    ///< [m] a ball centre at most this far from the surface + radius
  double max_age = 0.1;         ///< [s] an estimate older than this is stale (never acted on)
  double sigma_stereo = 0.002;  ///< [m] measurement std of a triangulated ball
  double sigma_mono = 0.006;    ///< [m] ... of a ball placed on the surface from one camera
  double search_px = 40.0;      ///< [pixels] search around the predicted ball while tracking
  /// A ball blob whose radius is below this fraction of a whole ball's at its distance is taken
  /// as partly hidden (its centre is off): the camera that sees the whole ball places it alone.
  double partial_ratio = 0.85;
};

struct StereoModel {
  StereoModel(Calibration calibration, field::Field field, StereoConfig config = {});
  Calibration calibration;
  field::Field field;
  StereoConfig config;
  /// [pixels] per camera: the radius range in which a ball / the cup's opening is searched
  /// (from the calibration and the lane: nearest and farthest lane point, with slack).
  std::vector<std::array<double, 2>> ball_radius_px, hole_radius_px;
};

/// Where one object was found in one frame.
struct Sighting {
  int views = 0;  ///< 2: triangulated; 1: one camera, on the surface; 0: not found
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< [m] world
  double reprojection_px = 0.0;                     ///< (views == 2) the larger of the two
  std::array<Blob, 2> blobs{};                      ///< the first two cameras' detections
  bool gated = false;    ///< found in both images but refused (reprojection or off the surface)
  bool partial = false;  ///< one camera's blob was partly hidden; placed by the other
};

struct StereoData {
  explicit StereoData(const StereoModel& model);
  std::vector<Detector> detectors;
  Track ball;
  Eigen::Vector3d hole_sum = Eigen::Vector3d::Zero();
  int hole_count = 0;
  double hole_last = -1e300;  ///< [s] stamp of the last hole sighting
  Sighting last_ball, last_hole;
  long frames = 0;
};

/// What the pipeline believes at `now`.
struct StereoEstimate {
  bool ball_fresh = false;  ///< a ball measurement at most max_age old
  bool hole_known = false;
  bool ball_in_cup = false;  ///< the ball vanished within a cup radius of the hole
  Eigen::Vector3d ball = Eigen::Vector3d::Zero();  ///< [m] filtered, at the last frame's time
  Eigen::Vector3d hole = Eigen::Vector3d::Zero();  ///< [m]
  double ball_age = 1e300;                         ///< [s] since the last accepted ball measurement
};

/// Locates one object in the first two images (`ball`: the ball, else the hole), without memory.
Sighting locate(const StereoModel& model, StereoData& data, const viz::Image* const* images,
                bool ball, const std::optional<Eigen::Vector2d>* predicted = nullptr);

/// One stereo frame captured at `stamp` [s]: locates the ball and the hole, updates the track.
void stereo_frame(const StereoModel& model, StereoData& data, const viz::Image* const* images,
                  double stamp);

StereoEstimate stereo_estimate(const StereoModel& model, const StereoData& data, double now);

/// [s] CPU time of the calling thread (what the pipeline costs, apart from rendering).
double thread_cpu_seconds();

}  // namespace mg::vision
