#pragma once
/// The model of a World: its MJCF text and its compilation (world_mjcf.cpp), and the layout of
/// the user data every mjData of a world carries. For World (world.cpp) and tests.
#include <string>

#include "field/field.hpp"
#include "sim/mujoco_handles.hpp"
#include "sim/world.hpp"

namespace mg::sim {

/// mjData::userdata of a world (the model's nuserdata): the hole the ground is cut away under
/// (centre [m], radius [m]), the last solved ground normal force [N] and the speed into a border
/// or obstacle face resolved in the last step [m/s] (0: none; sim/walls.hpp).
inline constexpr int kUserHoleX = 0, kUserHoleY = 1, kUserHoleRadius = 2, kUserGroundNormal = 3,
                     kUserWallImpact = 4, kUserSize = 5;

/// [m] How far the ground's collision geom drops while the ball's centre is over the hole
/// opening: out of reach, so the cup below catches the ball (World::update_ground_contact).
inline constexpr double kGroundDrop = 10.0;

/// The world's MJCF. `pairs`: MJCF <pair> elements; with them the model collides only those
/// geom pairs (collision="predefined"), without them MuJoCo's broadphase chooses.
std::string world_mjcf(const field::Field& field, const WorldOptions& options,
                       const std::string& pairs);

/// Compiles MJCF text from memory. Throws Error with MuJoCo's message if it is rejected.
ModelPtr compile_mjcf(const std::string& text);

/// Every geom pair MuJoCo's broadphase could hand to the narrow phase of `m`, as <pair> elements
/// with the contact parameters MuJoCo 2.2.2 would mix for it, in the order it visits them.
std::string predefined_pairs(const mjModel* m);

}  // namespace mg::sim
