#pragma once
/// Where the WAM stands and what it holds: the mount (base pose, club, joint friction of a plant)
/// and a mobile base's stance, with the published tables of wam_params.hpp. No simulator: the
/// arm as MJCF for MuJoCo is sim_backend/wam_mjcf.hpp.
///
/// Frames: the world has the ball tee at (0, 0), +x the default hitting direction, z up. The
/// WAM's DH frames 0..7 follow wam_params.hpp; frame 0 (the shoulder) sits on the base plate.
#include <array>

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

}  // namespace mg::robot
