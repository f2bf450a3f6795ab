#pragma once
/// The pinhole camera with Brown-Conrady distortion, in OpenCV's conventions (camera frame: x
/// right, y down, z along the optical axis; pixel (0, 0) is the centre of the top-left pixel),
/// and the geometry on it: projection, undistortion, rays, triangulation. Free functions over
/// value types; no OpenCV, no allocation (real-time safe).
#include <array>
#include <optional>
#include <string>

#include <Eigen/Dense>

#include "field/field.hpp"
#include "vision/rig.hpp"

namespace mg::vision {

struct CameraModel {
  std::string name;
  int width = 0, height = 0;                        ///< [pixels]
  double fx = 0, fy = 0;                            ///< [pixels] focal lengths
  double cx = 0, cy = 0;                            ///< [pixels] principal point
  std::array<double, 5> dist{};                     ///< k1 k2 p1 p2 k3
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< world -> camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      ///< camera = R * world + t [m]
  double rate_hz = 60.0;                            ///< [Hz]
  double latency = 0.0;                             ///< [s]

  /// [m] The optical centre in the world frame.
  Eigen::Vector3d centre() const { return -R.transpose() * t; }
  Eigen::Matrix3d K() const;
};

/// The exact model of a rig camera (what the simulator renders): square pixels, the principal
/// point at the image centre, fy = (height / 2) / tan(fovy / 2).
CameraModel camera_from_spec(const CameraSpec& spec);

/// Distorts normalised ideal coordinates (x/z, y/z).
Eigen::Vector2d distort(const std::array<double, 5>& dist, const Eigen::Vector2d& ideal);
/// Inverts `distort` by fixed-point iteration (20 steps; exact to 1e-9 for |k1| < 0.3 in the
/// image).
Eigen::Vector2d undistort(const std::array<double, 5>& dist, const Eigen::Vector2d& distorted);

/// The pixel of world point `p` [m]; nullopt when it is behind the camera (z <= 1 mm).
std::optional<Eigen::Vector2d> project(const CameraModel& camera, const Eigen::Vector3d& p);
/// True when `pixel` lies in the image (with `margin` pixels to spare).
bool in_image(const CameraModel& camera, const Eigen::Vector2d& pixel, double margin = 0.0);

/// The world ray through `pixel` (undistorted): origin the optical centre, unit direction.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
};
Ray pixel_ray(const CameraModel& camera, const Eigen::Vector2d& pixel);

/// The point nearest two rays (the middle of their common perpendicular), by least squares on
/// the ray parameters; nullopt for (nearly) parallel rays.
std::optional<Eigen::Vector3d> triangulate(const Ray& a, const Ray& b);
/// Triangulates and refines the point by Gauss-Newton on the reprojection error in both images
/// (5 steps). nullopt for parallel rays or a point behind a camera.
std::optional<Eigen::Vector3d> triangulate(const CameraModel& a, const Eigen::Vector2d& pa,
                                           const CameraModel& b, const Eigen::Vector2d& pb);
/// [pixels] The larger of the two reprojection errors of `p`; infinity behind a camera.
double reprojection_error(const CameraModel& a, const Eigen::Vector2d& pa, const CameraModel& b,
                          const Eigen::Vector2d& pb, const Eigen::Vector3d& p);

/// Where the ray through `pixel` meets the surface `above` metres over the field's ground
/// (a ball's centre: above = its radius); one camera's estimate when the other has lost the
/// ball. nullopt when the ray misses the lane or points up.
std::optional<Eigen::Vector3d> intersect_surface(const CameraModel& camera,
                                                 const Eigen::Vector2d& pixel,
                                                 const field::Field& field, double above);

}  // namespace mg::vision
