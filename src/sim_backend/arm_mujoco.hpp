#pragma once
/// The WAM in a compiled MuJoCo model (the simulator's side of the arm): its MuJoCo addresses,
/// an ArmModel from the compiled model's limits, and the functions that read and write the arm's
/// part of a simulation. The controller never includes this (sim_backend/mujoco_arm.hpp does, the
/// adapter).
#include <mujoco/mujoco.h>

#include <array>
#include <string>

#include "robot/arm_model.hpp"
#include "sim/mujoco_handles.hpp"

namespace mg::robot {

/// Where the arm is in one compiled model: joints `wam_j1..7`, motors `wam_m1..7`, site
/// `club_face`, body `wam_link7`. Plain indices (cheap to copy, valid for that model only).
struct ArmIds {
  std::array<int, kNumJoints> qpos{-1, -1, -1, -1, -1, -1, -1};      ///< d->qpos addresses
  std::array<int, kNumJoints> dof{-1, -1, -1, -1, -1, -1, -1};       ///< d->qvel addresses
  std::array<int, kNumJoints> actuator{-1, -1, -1, -1, -1, -1, -1};  ///< d->ctrl indices
  int site = -1;                                                     ///< club_face
  int flange_body = -1;                                              ///< wam_link7
};

/// Looks the arm's names up in `m`. Throws mg::InputError if one is missing or a joint is not a
/// hinge.
ArmIds find_arm_ids(const mjModel* m);

/// The arm model with the position limits, armature, damping, torque limits and gravity of the
/// compiled model `m`. Throws mg::InputError if a name is missing or if the compiled shoulder
/// frame does not match `mount` (so DH and MuJoCo routes agree).
ArmModel arm_model_from_mujoco(const mjModel* m, const WamMount& mount);

/// Compiles MJCF text in memory; throws mg::Error with MuJoCo's message on failure.
sim::ModelPtr compile_mjcf(const std::string& xml);

// ---- reading and writing a simulation (real-time safe: no allocation, no throw) ----

/// [rad] arm joint positions from d->qpos, (7).
Vector7 joint_positions(const ArmIds& arm, const mjData* d);
/// [rad/s] arm joint velocities from d->qvel, (7).
Vector7 joint_velocities(const ArmIds& arm, const mjData* d);
/// Writes the arm joint positions into d->qpos (other entries untouched).
void set_joint_positions(const ArmIds& arm, mjData* d, const Vector7& q);

/// world_T_face from d->site_xpos/site_xmat (valid after mj_kinematics or mj_forward).
Eigen::Isometry3d club_pose(const ArmIds& arm, const mjData* d);
/// world_T_7: the flange (link-7 body) frame from d->xpos/xmat.
Eigen::Isometry3d flange_pose(const ArmIds& arm, const mjData* d);

/// Club-face Jacobian via mj_jacSite, world frame: rows 0-2 linear [m/rad], rows 3-5 angular
/// [rad/rad], columns = arm joints. Needs mj_kinematics + mj_comPos (or mj_forward) on `d`;
/// scratch memory comes from the mjData stack.
void club_jacobian(const ArmIds& arm, const mjModel* m, mjData* d, Matrix67& jacobian);

}  // namespace mg::robot
