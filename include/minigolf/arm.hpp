#pragma once
/// minigolf C++ API: the arm (docs/robot.md, docs/hardware.md): the WAM's model, kinematics and
/// dynamics, and the control boundary every backend implements, read -> update -> write
/// (mg::control::MeasuredState in, mg::control::ModuleCommand out; MuJoCo is one backend,
/// mg::control::MujocoArm).
#include "control/arm_interface.hpp"
#include "robot/arm_model.hpp"
#include "robot/dynamics.hpp"
#include "robot/ik.hpp"
#include "robot/kinematics.hpp"
#include "robot/wam_model.hpp"
#include "sim_backend/mujoco_arm.hpp"
