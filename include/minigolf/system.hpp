#pragma once
/// minigolf C++ API: a ready system and its putts (docs/cpp-api.md).
///
///   const mg::system::System sys(mg::system::load_config("", "flat"));  // immutable, share it
///   mg::system::SystemData data(sys);                                   // one per thread
///   mg::system::PuttSpec spec;  spec.angle = 0.02;  spec.speed = 1.2;   // [rad], [m/s] (club)
///   mg::system::PuttReport r = mg::system::putt(sys, data, spec);       // the arm hits
///   r.outcome.sunk, r.outcome.rest_position, r.launch.speed
///
/// mg::system::putt is what `minigolf putt` and Python's System.putt run; mg::system::parallel_for
/// runs many putts on threads (the same bits for any thread count).
#include "system/distributed.hpp"
#include "system/parallel.hpp"
#include "system/putt.hpp"
#include "system/system.hpp"
