#pragma once
/// minigolf C++ API: fields (docs/fields.md) and plants (docs/reality.md).
///
///   mg::field::Field f = mg::field::load_field("flat");  // shipped name or a YAML file
///   double z = f.height(x, y);                            // [m]
///   f.hole.position, f.tee, f.situations                  // [m], world frame
///
/// A field is what the robot believes (its field file); a plant (mg::plant::Plant) says where the
/// world really differs (grass, tilt, hole, club, arm friction, vision). Units: SI, radians.
#include "field/field.hpp"
#include "field/obstacles.hpp"
#include "field/situations.hpp"
#include "field/surface.hpp"
#include "plant/plant.hpp"
