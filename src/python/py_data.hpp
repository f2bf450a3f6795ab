#pragma once
/// What the binding files share: the Python `Data` (an mjData of a world) and the bindings that
/// live in files of their own.
#include <pybind11/pybind11.h>

#include <mujoco/mujoco.h>

#include "core/error.hpp"
#include "sim/world.hpp"

namespace mg::python {

/// An mjData of a world: owned (World.make_data) or borrowed from a SystemData.
struct Data {
  const sim::World* world = nullptr;
  sim::DataPtr owned;
  mjData* d = nullptr;
};

/// Throws unless `d` is an mjData of `w` (another world's would be read out of bounds).
inline mjData* data_of(const sim::World& w, const Data& d) {
  if (d.world != &w) throw InputError("World: this Data belongs to another world (use that world's make_data)");
  return d.d;
}

/// minigolf.Renderer (render_bindings.cpp).
void bind_render(pybind11::module_& m);

}  // namespace mg::python
