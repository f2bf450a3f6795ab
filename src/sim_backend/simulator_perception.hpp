#pragma once
/// Perception in simulator mode: the ground truth of a running simulation, and the hook through
/// which a putt's module sees that simulation through other eyes (rendered cameras).
#include "perception/perception.hpp"
#include "sim/world.hpp"

namespace mg::perception {

/// Makes the perception a full-system putt's module reads from the simulation it runs, in place
/// of the simulator's truth (control::FullPuttOptions::perception_source): the cameras of
/// vision/camera_perception.hpp render `world` in the state `d`. Called once per putt after the
/// ball is placed; the perception returned stays valid until the next call. Not thread-safe:
/// one source per thread.
class PerceptionSource {
 public:
  virtual ~PerceptionSource() = default;
  virtual Perception& attach(const sim::World& world, const mjData_* d) = 0;
};

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
