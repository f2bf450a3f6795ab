#pragma once
/// The minigolf C++ API: a simulated 7-DoF Barrett WAM in MuJoCo that learns to putt.
///
/// One header per part (include only what you use), all of them here:
///   minigolf/field.hpp        fields and plants                         mg::field, mg::plant
///   minigolf/world.hpp        MuJoCo worlds, ball-only putts            mg::sim
///   minigolf/arm.hpp          the WAM and the arm interface             mg::robot, mg::control
///   minigolf/module.hpp       the module, its config and hitting DS     mg::control, mg::ds
///   minigolf/system.hpp       a ready system and its putts              mg::system
///   minigolf/learner.hpp      hitting-parameter learners                mg::learning, mg::stats
///   minigolf/teacher.hpp      the teacher and self-teaching             mg::teacher, mg::selfteach
///   minigolf/experiments.hpp  sweeps, collection, evaluation, reproduce mg::experiments
///   minigolf/game.hpp         courses, the planner, rounds              mg::game
/// Every subsystem header is installed too (minigolf/<subsystem>/<file>.hpp): the types are
/// defined there. Errors: exceptions derived from mg::Error (minigolf/core/error.hpp), InputError
/// for bad input, IoError for files, NumericalError; messages name the quantity. Units: SI and
/// radians. Shipped data (fields, models, data sets): mg::data_dir() (minigolf/core/io.hpp).
/// CMake: find_package(minigolf) and link minigolf::minigolf (docs/cpp-api.md).
#include "core/error.hpp"
#include "core/io.hpp"
#include "minigolf/arm.hpp"
#include "minigolf/experiments.hpp"
#include "minigolf/field.hpp"
#include "minigolf/game.hpp"
#include "minigolf/learner.hpp"
#include "minigolf/module.hpp"
#include "minigolf/system.hpp"
#include "minigolf/teacher.hpp"
#include "minigolf/world.hpp"
