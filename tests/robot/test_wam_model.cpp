// The WAM's mount and club as the robot models them (robot/wam_model.hpp); the MJCF made from
// them is checked in tests/sim_backend/test_wam_mjcf.cpp.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/error.hpp"
#include "robot/arm_model.hpp"
#include "robot/kinematics.hpp"
#include "robot/wam_model.hpp"

namespace mg::robot {
namespace {

TEST(WamModel, ClubFaceGeometryFollowsTheLieAngle) {
  const ClubGeometry club;
  const Eigen::Isometry3d face = club_face_in_flange(club);
  const Eigen::Vector3d shaft_up = -Eigen::Vector3d::UnitZ();
  // Zero loft: the face normal is perpendicular to the shaft.
  EXPECT_NEAR(face.linear().col(0).dot(shaft_up), 0.0, 1e-12);
  // With the face vertical the shaft leans (pi/2 - lie) from vertical, towards the heel side.
  EXPECT_NEAR(std::acos(face.linear().col(2).dot(shaft_up)), kPi / 2 - club.lie_angle, 1e-12);
  EXPECT_GT(face.linear().col(1).dot(-face.translation()),
            0.0);  // heel axis points back to the shaft
  EXPECT_TRUE(face.linear().isUnitary(1e-12));
  EXPECT_NEAR(face.linear().determinant(), 1.0, 1e-12);
}

TEST(WamModel, ClubInertialIsPhysical) {
  const LinkInertial c = club_inertial(ClubGeometry{});
  EXPECT_NEAR(c.mass, 0.4, 1e-12);
  Eigen::Matrix3d i;
  i << c.inertia[0], c.inertia[3], c.inertia[4], c.inertia[3], c.inertia[1], c.inertia[5],
      c.inertia[4], c.inertia[5], c.inertia[2];
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(i).eigenvalues();
  EXPECT_GT(ev.minCoeff(), 0.0);
  EXPECT_LE(ev(2), ev(0) + ev(1) + 1e-15);  // triangle inequality
}

TEST(WamModel, ABadMountIsRejectedWithANamedError) {
  WamMount mount;
  mount.club.shaft_length = -1.0;
  EXPECT_THROW((void)ArmModel(mount), InputError);
}

}  // namespace
}  // namespace mg::robot
