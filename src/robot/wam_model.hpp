#pragma once
/// The WAM + golf club as MJCF, generated from the published tables in wam_params.hpp.
///
/// Body frames of `wam_link1..7` coincide with the DH link frames 1..7, so COMs and inertia
/// tensors are written as tabulated, in the DH link frames (the tensor as principal moments and
/// axes computed in double precision, see wam_model.cpp for why not `fullinertia`). Joint i turns
/// about z of frame i-1; in body i that axis and point are R_x(alpha_i)^T z and -R_x(alpha_i)^T
/// (a_i, 0, d_i).
///
/// Names: joints `wam_j1..7`, bodies `wam_base`, `wam_link1..7`, `wam_club`, actuators `wam_m1..7`,
/// site `club_face`, geom `club_head` (the only colliding geom: contype 4, conaffinity 0).
/// The generated XML uses radians: the enclosing model needs `<compiler angle="radian"/>`.
#include <array>
#include <string>

#include "robot/wam_params.hpp"

namespace mg::robot {

/// Where the arm stands and what it holds. World frame: ball tee at (0, 0), +x the default
/// hitting direction, z up, lane surface near z = 0, lane y in [-0.6, 0.6].
struct WamMount {
  /// [m] world position of the centre of the base mounting plate. Default: 0.15 m outside the
  /// lane edge on a 0.5 m pedestal, a little behind the tee (the reachability check behind the
  /// choice is in notes/robot.md and tests/robot/test_ik.cpp).
  std::array<double, 3> base_position{-0.25, 0.75, 0.50};
  /// [rad] yaw of the base about world z; -pi/2 makes frame 0's x axis point at the lane (-y), so
  /// J1 works around the middle of its range.
  double base_yaw = -kPi / 2;
  /// Club geometry and mass.
  ClubGeometry club{};
  /// Draw a visual (non-colliding, massless) pedestal column from z = 0 up to the plate.
  bool pedestal = true;
  /// [N m] Coulomb friction per joint (MJCF `frictionloss`; 0: none, as in the robot's model).
  /// A plant's truth (plant/plant.hpp): the module's model never has it.
  std::array<double, kNumJoints> joint_friction{};

  /// Throws mg::InputError naming the field if a value is non-finite or implausible.
  void validate() const;
};

/// Where a mobile base stands for one stroke (a player walks to the ball): the robot's own frame
/// (the one its module, hitting DS, envelope and learned models live in: ball foot point at the
/// origin, default hitting direction +x) placed in the world at `position` [m] (the ball's foot
/// point: ball x, y and the ground height there), turned by `yaw` [rad] about z. world = R(yaw)
/// local + position. The identity is the fixed arm beside the field's tee at the origin.
struct Stance {
  std::array<double, 3> position{0.0, 0.0, 0.0};
  double yaw = 0.0;
  bool identity() const {
    return position[0] == 0.0 && position[1] == 0.0 && position[2] == 0.0 && yaw == 0.0;
  }
  bool operator==(const Stance&) const = default;
  /// A point of the robot's frame in the world, and back [m].
  std::array<double, 3> to_world(const std::array<double, 3>& local) const;
  std::array<double, 3> to_local(const std::array<double, 3>& world) const;
};

/// `local` (a mount in the robot's frame) placed by `stance`: the base where it stands in the
/// world. The identity stance gives `local` exactly.
WamMount mount_at(const WamMount& local, const Stance& stance);

/// [rad] (7) rest posture for the default mount: the club face at about (-0.175, 0, 0.16) m,
/// vertical, normal along +x; at least 0.13 rad from every joint limit along the IK solutions over
/// the whole hitting region (notes/robot.md). Also a good IK start and null-space posture.
inline constexpr std::array<double, kNumJoints> kDefaultRestPosture{0.0413,  0.8483, 0.1533, 2.4368,
                                                                    -2.8162, 0.5102, -0.1911};

/// `<body>` XML for the arm (base, links, club) to insert into a `<worldbody>`.
std::string wam_bodies_mjcf(const WamMount& mount);

/// The children of an `<actuator>` element: torque motors `wam_m1..7`, gear 1, ctrlrange =
/// kTorqueLimit.
std::string wam_actuators_mjcf();

/// A complete model: the arm alone (no ground), gravity on, 1 ms Euler steps.
std::string wam_standalone_mjcf(const WamMount& mount);

}  // namespace mg::robot
