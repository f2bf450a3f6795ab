#pragma once
/// The WAM + golf club as MJCF, generated from the published tables in robot/wam_params.hpp (the
/// simulator's side of the arm; the controller never includes this).
///
/// Body frames of `wam_link1..7` coincide with the DH link frames 1..7, so COMs and inertia
/// tensors are written as tabulated, in the DH link frames (the tensor as principal moments and
/// axes computed in double precision, see wam_mjcf.cpp for why not `fullinertia`). Joint i turns
/// about z of frame i-1; in body i that axis and point are R_x(alpha_i)^T z and -R_x(alpha_i)^T
/// (a_i, 0, d_i).
///
/// Names: joints `wam_j1..7`, bodies `wam_base`, `wam_link1..7`, `wam_club`, actuators `wam_m1..7`,
/// site `club_face`, geom `club_head` (the only colliding geom: contype 4, conaffinity 0).
/// The generated XML uses radians: the enclosing model needs `<compiler angle="radian"/>`.
#include <string>

#include "robot/wam_model.hpp"

namespace mg::robot {

/// `<body>` XML for the arm (base, links, club) to insert into a `<worldbody>`. Validates the
/// mount (mg::InputError).
std::string wam_bodies_mjcf(const WamMount& mount);

/// The children of an `<actuator>` element: torque motors `wam_m1..7`, gear 1, ctrlrange =
/// kTorqueLimit.
std::string wam_actuators_mjcf();

/// A complete model: the arm alone (no ground), gravity on, 1 ms Euler steps.
std::string wam_standalone_mjcf(const WamMount& mount);

}  // namespace mg::robot
