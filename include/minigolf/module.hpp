#pragma once
/// minigolf C++ API: the minigolf module (docs/control.md, docs/ds.md): its configuration, its
/// state machine (Idle, Rest, Hitting, Braking), the hitting motion it follows (a SEDS dynamical
/// system bent to any angle and speed), what it perceives, and the lockstep full-system putt.
///
///   mg::control::ModuleConfig config = mg::system::load_config("", "flat");
///   mg::ds::HittingModel model = mg::ds::read_hitting_model(config.hitting_model);
#include "control/minigolf_module.hpp"
#include "control/module_config.hpp"
#include "control/module_state.hpp"
#include "ds/demonstrations.hpp"
#include "ds/hitting_ds.hpp"
#include "ds/hitting_model.hpp"
#include "ds/seds.hpp"
#include "perception/perception.hpp"
#include "sim_backend/full_system.hpp"
