#pragma once
/// Forward kinematics of the WAM + club from the DH table, independent of MuJoCo.
///
/// Every function here is real-time safe: no allocation, no exceptions (fixed-size Eigen types).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "robot/wam_params.hpp"

namespace mg::robot {

using Vector7 = Eigen::Matrix<double, 7, 1>;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix67 = Eigen::Matrix<double, 6, 7>;
using Matrix7 = Eigen::Matrix<double, 7, 7>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// Homogeneous transform A_i(q_i) of DH frame i in frame i-1 (Spong), i = 1..7.
Eigen::Isometry3d dh_link_transform(int i, double q);

/// Transforms of DH frames 1..7 in frame 0 (shoulder frame): frames[i-1] = 0_T_i. (7)
void dh_link_frames(const Vector7& q, std::array<Eigen::Isometry3d, kNumJoints>& frames);

/// 0_T_7: the flange (link-7) frame in frame 0, as a 4x4 homogeneous transform. q [rad] (7).
Eigen::Isometry3d dh_forward_kinematics(const Vector7& q);

/// Pose of the `club_face` frame in the flange frame: x = face normal (out of the face),
/// y = towards the heel (the shaft side), z = up along the face.
Eigen::Isometry3d club_face_in_flange(const ClubGeometry& club);

/// Rigid-body parameters of the whole club (shaft + head) in the flange frame.
LinkInertial club_inertial(const ClubGeometry& club);

/// Sum of two rigid bodies given in the same frame (parallel-axis theorem).
LinkInertial combine_inertials(const LinkInertial& a, const LinkInertial& b);

/// World transform of frame 0 for a base mounted at `base_position` [m, world] with yaw
/// `base_yaw` [rad] about world z.
Eigen::Isometry3d shoulder_in_world(const std::array<double, 3>& base_position, double base_yaw);

/// Rotation matrix of a rotation vector (unit axis * angle [rad]).
Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& axis_angle);

/// Rotation vector (axis * angle, angle in [0, pi]) of R.
Eigen::Vector3d rotation_to_vector(const Eigen::Matrix3d& r);

}  // namespace mg::robot
