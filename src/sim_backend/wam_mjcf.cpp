#include "sim_backend/wam_mjcf.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstring>
#include <memory>

#include "robot/kinematics.hpp"
#include "sim/world.hpp"

namespace mg::robot {
namespace {

std::string vec3(const Eigen::Vector3d& v) {
  return fmt::format("{:.17g} {:.17g} {:.17g}", v.x(), v.y(), v.z());
}

std::string quat(const Eigen::Matrix3d& r) {
  Eigen::Quaterniond q(r);
  q.normalize();
  return fmt::format("{:.17g} {:.17g} {:.17g} {:.17g}", q.w(), q.x(), q.y(), q.z());
}

// The full tensor in the link frame, written as principal moments + principal axes computed here in
// double precision. MuJoCo 2.2.2 diagonalises `fullinertia` itself, but measured against the tables
// its result is off by up to 2.4e-8 kg m^2 (link 1, 2e-7 relative), which alone would cap the
// agreement of our inverse dynamics with mj_inverse at ~3e-8; this way it is ~1e-15.
std::string inertial(const LinkInertial& l) {
  const auto& i = l.inertia;
  Eigen::Matrix3d tensor;
  tensor << i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2];
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(tensor);
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2);
  const Eigen::Vector3d moments = eig.eigenvalues();
  return fmt::format(
      R"(<inertial pos="{:.17g} {:.17g} {:.17g}" mass="{:.17g}" quat="{}" diaginertia="{}"/>)",
      l.com[0], l.com[1], l.com[2], l.mass, quat(axes), vec3(moments));
}

// Visual-only geoms: no collisions, no mass (the inertials are explicit).
constexpr const char* kVisual = R"(contype="0" conaffinity="0" group="1" mass="0")";

// Visual geoms of link i (frame i): a capsule from the joint-i axis point (the origin of frame i-1)
// to the origin of frame i, and a short cylinder along the joint axis as the motor housing.
std::string link_visuals(int i, const Eigen::Vector3d& joint_pos,
                         const Eigen::Vector3d& joint_axis) {
  std::string out;
  const double radius = i <= 4 ? 0.045 : 0.03;
  if (joint_pos.norm() > 1e-6)
    out += fmt::format(
        R"(<geom type="capsule" fromto="{} 0 0 0" size="{}" rgba="0.75 0.75 0.78 1" {}/>)",
        vec3(joint_pos), radius * 0.8, kVisual);
  const Eigen::Vector3d a = joint_pos - 0.6 * radius * joint_axis,
                        b = joint_pos + 0.6 * radius * joint_axis;
  out += fmt::format(R"(<geom type="cylinder" fromto="{} {}" size="{}" rgba="0.2 0.2 0.22 1" {}/>)",
                     vec3(a), vec3(b), radius, kVisual);
  return out;
}

std::string club_body(const ClubGeometry& c) {
  const Eigen::Isometry3d face = club_face_in_flange(c);
  const Eigen::Vector3d head_centre =
      face.translation() - 0.5 * c.head_thickness * face.linear().col(0);
  std::string out = R"(<body name="wam_club">)";
  out += inertial(club_inertial(c));
  out += fmt::format(
      R"(<geom name="club_shaft" type="capsule" fromto="0 0 0 0 0 {:.17g}" size="{:.17g}" rgba="0.6 0.6 0.65 1" {}/>)",
      c.shaft_length, c.shaft_radius, kVisual);
  // The head is the only colliding part of the arm: bit 4 meets the ball, nothing else.
  // Its contact parameters win over the ball's (priority): a spring-damper with the face's
  // restitution, MuJoCo solref = (time constant, damping ratio) with natural frequency
  // 1 / (time constant * damping ratio) = 2 pi / face_contact_period.
  const double zeta = sim::damping_ratio_for_restitution(c.face_restitution);
  const double time_constant = c.face_contact_period / (2.0 * kPi * zeta);
  out += fmt::format(
      R"(<geom name="club_head" type="box" pos="{}" quat="{}" size="{:.17g} {:.17g} {:.17g}" contype="4" conaffinity="0" condim="3" priority="2" friction="0.3 0 0" solref="{:.17g} {:.17g}" mass="0" rgba="0.15 0.15 0.15 1"/>)",
      vec3(head_centre), quat(face.linear()), 0.5 * c.head_thickness, 0.5 * c.head_length,
      0.5 * c.head_height, time_constant, zeta);
  out +=
      fmt::format(R"(<site name="club_face" pos="{}" quat="{}" size="0.005" rgba="1 0.2 0.2 1"/>)",
                  vec3(face.translation()), quat(face.linear()));
  out += "</body>";
  return out;
}

}  // namespace

std::string wam_bodies_mjcf(const WamMount& mount) {
  mount.validate();
  std::string out = fmt::format(
      R"(<body name="wam_base" pos="{:.17g} {:.17g} {:.17g}" quat="{}">)", mount.base_position[0],
      mount.base_position[1], mount.base_position[2],
      quat(Eigen::AngleAxisd(mount.base_yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix()));
  // Static base: its inertia never enters the dynamics, but MuJoCo wants a positive mass.
  out += R"(<inertial pos="0 0 0.15" mass="10" diaginertia="0.1 0.1 0.05"/>)";
  // Base housing from the plate up to just under the shoulder; pedestal down to the floor.
  out += fmt::format(
      R"(<geom type="cylinder" fromto="0 0 0 0 0 {:.17g}" size="0.09" rgba="0.3 0.3 0.32 1" {}/>)",
      kShoulderHeight - 0.08, kVisual);
  if (mount.pedestal && mount.base_position[2] > 0.0)
    out += fmt::format(
        R"(<geom type="cylinder" fromto="0 0 {:.17g} 0 0 0" size="0.07" rgba="0.45 0.4 0.35 1" {}/>)",
        -mount.base_position[2], kVisual);

  // Nested bodies: body i in body i-1 at (a_i, 0, d_i), rotated R_x(alpha_i) (theta = 0).
  int open = 0;
  for (int i = 1; i <= kNumJoints; ++i) {
    const DhRow& row = kDhTable[static_cast<std::size_t>(i - 1)];
    const Eigen::Matrix3d rx =
        Eigen::AngleAxisd(row.alpha, Eigen::Vector3d::UnitX()).toRotationMatrix();
    Eigen::Vector3d pos(row.a, 0.0, row.d);
    const Eigen::Vector3d joint_pos = -rx.transpose() * pos;
    const Eigen::Vector3d joint_axis = rx.transpose() * Eigen::Vector3d::UnitZ();
    if (i == 1) pos.z() += kShoulderHeight;  // frame 0 sits above the plate
    const auto k = static_cast<std::size_t>(i - 1);
    out += fmt::format(R"(<body name="wam_link{}" pos="{}" quat="{}">)", i, vec3(pos), quat(rx));
    out += fmt::format(
        R"(<joint name="wam_j{}" type="hinge" pos="{}" axis="{}" limited="true" range="{:.17g} {:.17g}" armature="{:.17g}" damping="{:.17g}"/>)",
        i, vec3(joint_pos), vec3(joint_axis), kJointLower[k], kJointUpper[k], kArmature[k],
        kDamping[k]);
    if (mount.joint_friction[k] > 0.0)  // only then: a mount without friction is the same XML
      out.insert(out.size() - 2,
                 fmt::format(R"( frictionloss="{:.17g}")", mount.joint_friction[k]));
    out += inertial(kLinkInertials[k]);
    out += link_visuals(i, joint_pos, joint_axis);
    ++open;
  }
  out += club_body(mount.club);
  for (int i = 0; i < open; ++i) out += "</body>";
  out += "</body>";
  return out;
}

std::string wam_actuators_mjcf() {
  std::string out;
  for (int i = 1; i <= kNumJoints; ++i) {
    const double limit = kTorqueLimit[static_cast<std::size_t>(i - 1)];
    out += fmt::format(
        R"(<motor name="wam_m{0}" joint="wam_j{0}" gear="1" ctrllimited="true" ctrlrange="{1:.17g} {2:.17g}"/>)",
        i, -limit, limit);
  }
  return out;
}

std::string wam_standalone_mjcf(const WamMount& mount) {
  return fmt::format(R"(<mujoco model="wam_standalone">
  <compiler angle="radian"/>
  <option timestep="0.001" gravity="0 0 -9.81"/>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1"/>
    {}
  </worldbody>
  <actuator>{}</actuator>
</mujoco>
)",
                     wam_bodies_mjcf(mount), wam_actuators_mjcf());
}

}  // namespace mg::robot
