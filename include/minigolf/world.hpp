#pragma once
/// minigolf C++ API: the MuJoCo world of a field and ball-only putts (docs/physics.md).
///
///   const mg::sim::World world(mg::field::load_field("flat"));  // immutable, share it
///   mg::sim::DataPtr d = world.make_data();                      // one per thread
///   mg::sim::PuttRequest q;  q.angle = 0.0;  q.speed = 2.0;      // [rad], [m/s]
///   mg::sim::PuttOutcome out = mg::sim::simulate_putt(world, d.get(), world.field().hole.position,
///   q);
///
/// mg::sim::fast_putt gives the same outcome much faster where it applies. The library sets no
/// process-wide MuJoCo callback; mg::sim::exit_on_mujoco_error() is a program's choice.
#include "sim/fast_putt.hpp"
#include "sim/mujoco_errors.hpp"
#include "sim/mujoco_handles.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"
