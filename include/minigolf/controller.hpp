#pragma once
/// minigolf C++ API: the controller alone (docs/cpp-api.md, docs/hardware.md): the minigolf
/// module (config, state machine, the 500 Hz core update and its stages, the user and robot
/// updates), the arm interface every backend implements (read -> update -> write), perception,
/// the WAM's model, kinematics, dynamics and IK, and the hitting DS the module follows. Nothing
/// here includes or links a simulator: link minigolf::controller
/// (find_package(minigolf COMPONENTS controller)) and bring your own ArmBackend.
#include "control/arm_interface.hpp"
#include "control/console_command.hpp"
#include "control/minigolf_module.hpp"
#include "control/module_config.hpp"
#include "control/module_stages.hpp"
#include "control/module_state.hpp"
#include "control/recorder.hpp"
#include "core/io.hpp"
#include "ds/hitting_model.hpp"
#include "perception/perception.hpp"
#include "robot/arm_model.hpp"
#include "robot/dynamics.hpp"
#include "robot/ik.hpp"
#include "robot/kinematics.hpp"
#include "robot/wam_model.hpp"
