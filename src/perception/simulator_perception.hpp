#pragma once
/// Perception in simulator mode: the ground truth of a running simulation.
#include "perception/perception.hpp"
#include "sim/world.hpp"

namespace mg::perception {

/// Ground truth from a running simulation: always fresh, age 0. Holds references: `world` and
/// `data` must outlive it. Real-time safe (no allocation).
class SimulatorPerception final : public Perception {
 public:
  SimulatorPerception(const sim::World& world, const mjData* data) : world_(&world), data_(data) {}
  Perceived perceive(double now) noexcept override;

 private:
  const sim::World* world_;
  const mjData* data_;
};

}  // namespace mg::perception
