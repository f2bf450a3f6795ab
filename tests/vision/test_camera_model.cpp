// Camera geometry against independent routes: projection through the rig's pose by hand,
// undistortion inverts distortion, triangulation of exact pixels returns the point, the
// one-camera estimate on the surface returns the ball.
#include <gtest/gtest.h>

#include <cmath>

#include "field/field.hpp"
#include "vision/camera_model.hpp"
#include "vision/rig.hpp"

namespace mg::vision {
namespace {

CameraSpec spec(std::array<double, 3> pos, Distortion d = {}) {
  CameraSpec s;
  s.name = std::string(1, 'c');  // (a literal here trips GCC 12's -Wrestrict)
  s.position = pos;
  s.look_at = {1.2, 0.0, 0.0};
  s.fovy_deg = 50;
  s.width = 640;
  s.height = 480;
  s.distortion = d;
  return s;
}

TEST(CameraModel, TheLookAtPointIsTheImageCentreAndUpIsUp) {
  const CameraModel c = camera_from_spec(spec({0.2, 1.0, 2.2}));
  const auto centre = project(c, {1.2, 0.0, 0.0});
  ASSERT_TRUE(centre);
  EXPECT_NEAR(centre->x(), 319.5, 1e-9);
  EXPECT_NEAR(centre->y(), 239.5, 1e-9);
  // A point above the look-at point is higher in the image (smaller row).
  const auto above = project(c, {1.2, 0.0, 0.3});
  ASSERT_TRUE(above);
  EXPECT_LT(above->y(), 239.5 - 10);
  // fy from the field of view: half the height at tan(25 deg) off the axis.
  EXPECT_NEAR(c.fy, 240.0 / std::tan(25.0 * M_PI / 180.0), 1e-9);
  EXPECT_FALSE(project(c, {0.2, 1.0, 3.0}));  // behind (above) the camera
}

TEST(CameraModel, UndistortInvertsDistort) {
  const std::array<double, 5> d{-0.05, 0.01, 0.001, -0.0005, 0.002};
  for (double x = -0.6; x <= 0.6; x += 0.15)
    for (double y = -0.45; y <= 0.45; y += 0.15) {
      const Eigen::Vector2d p(x, y);
      EXPECT_LT((undistort(d, distort(d, p)) - p).norm(), 1e-9) << x << "," << y;
    }
  // And distortion does move points (the check can fail).
  EXPECT_GT((distort(d, {0.6, 0.45}) - Eigen::Vector2d(0.6, 0.45)).norm(), 0.01);
}

TEST(CameraModel, TriangulationOfExactPixelsReturnsThePoint) {
  const Distortion d{-0.05, 0.01, 0, 0, 0};
  const CameraModel a = camera_from_spec(spec({0.2, 1.0, 2.2}, d)),
                    b = camera_from_spec(spec({2.2, 1.0, 2.2}, d));
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0.021), Eigen::Vector3d(2.0, 0.3, 0.05),
                                   Eigen::Vector3d(1.0, -0.5, 0.0)}) {
    const auto pa = project(a, p), pb = project(b, p);
    ASSERT_TRUE(pa && pb);
    const auto q = triangulate(a, *pa, b, *pb);
    ASSERT_TRUE(q);
    EXPECT_LT((*q - p).norm(), 1e-7);
    EXPECT_LT(reprojection_error(a, *pa, b, *pb, *q), 1e-6);
    // A pixel off by one in one image: a small reprojection error, a point off by millimetres.
    const auto r = triangulate(a, *pa + Eigen::Vector2d(1, 0), b, *pb);
    ASSERT_TRUE(r);
    EXPECT_GT((*r - p).norm(), 1e-3);
    EXPECT_LT((*r - p).norm(), 1e-2);
    EXPECT_GT(reprojection_error(a, *pa + Eigen::Vector2d(1, 0), b, *pb, *r), 0.2);
  }
}

TEST(CameraModel, OneCameraPlacesTheBallOnTheSurface) {
  const field::Field f = field::load_field("regular-hill");
  const CameraModel a = camera_from_spec(spec({0.2, 1.0, 2.2}, {-0.05, 0.01, 0, 0, 0}));
  for (const std::array<double, 2> xy :
       {std::array<double, 2>{0.0, 0.0}, {1.5, 0.2}, {2.2, -0.3}}) {
    const Eigen::Vector3d ball(xy[0], xy[1], f.height(xy[0], xy[1]) + f.ball.radius);
    const auto px = project(a, ball);
    ASSERT_TRUE(px);
    const auto p = intersect_surface(a, *px, f, f.ball.radius);
    ASSERT_TRUE(p);
    EXPECT_LT((*p - ball).norm(), 1e-6) << xy[0] << "," << xy[1];
  }
}

}  // namespace
}  // namespace mg::vision
