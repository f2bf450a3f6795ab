#pragma once
/// Finding the ball and the hole in one image (OpenCV inside, not in this header): colour masks
/// (the ball: bright and grey; the cup's opening: dark), connected components, size and shape
/// tests, and a sub-pixel centre from the intensity-weighted moments of the blob.
#include <memory>
#include <optional>

#include <Eigen/Dense>

#include "viz/image.hpp"

namespace mg::vision {

struct DetectorConfig {
  /// A ball pixel: bright enough (max channel at least this [0, 255]) and grey (saturation,
  /// (max - min) / max, at most ball_max_saturation): the lit and the shaded side of a white
  /// ball, not the green lane, not the ball's shadow on it.
  int ball_min_value = 60;
  double ball_max_saturation = 0.3;
  int hole_max_channel = 40;  ///< a hole pixel: every channel at most this
  double min_fill = 0.45;     ///< blob area / its bounding box's area, at least
  double max_aspect = 2.5;    ///< bounding box's long side / short side, at most
};

/// Candidates kept per image.
inline constexpr int kMaxCandidates = 6;

/// One blob found in an image.
struct Blob {
  bool found = false;
  Eigen::Vector2d pixel{0, 0};  ///< [pixels] sub-pixel centre (OpenCV convention)
  double radius = 0.0;          ///< [pixels] sqrt(area / pi)
  int candidates = 0;           ///< blobs that passed the tests (the nearest one is taken)
};

/// What to look for: the blob's expected radius range [pixels] and, when known, where
/// (a prediction) and how far from it [pixels].
struct BlobQuery {
  double min_radius = 1.0, max_radius = 50.0;
  std::optional<Eigen::Vector2d> near;
  double search_radius = 1e9;
};

/// Holds the masks and label buffers of one image size (one per camera and thread). The first
/// call for a size allocates; later calls reuse the buffers.
class Detector {
 public:
  explicit Detector(const DetectorConfig& config = {});
  ~Detector();
  Detector(Detector&&) noexcept;
  Detector& operator=(Detector&&) noexcept;
  const DetectorConfig& config() const;
  /// The blobs that pass the size and shape tests (none cut by the image's frame), best first
  /// (without `query.near`: rounder and larger; with it: nearer), at most `max` (<=
  /// kMaxCandidates) into `out`; returns how many.
  int balls(const viz::Image& image, const BlobQuery& query, Blob* out, int max);
  int holes(const viz::Image& image, const BlobQuery& query, Blob* out, int max);
  /// The best blob only.
  Blob ball(const viz::Image& image, const BlobQuery& query);
  Blob hole(const viz::Image& image, const BlobQuery& query);

  struct Impl;  ///< OpenCV's buffers (opaque)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace mg::vision
