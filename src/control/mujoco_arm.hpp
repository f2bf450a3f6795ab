#pragma once
/// The simulator as an arm backend (control/arm_interface.hpp): `read` takes the joint state from
/// the simulation (qpos/qvel at the arm's joints, d->time), `write` puts the torques on the arm's
/// motors (d->ctrl). Only the joints: the module gets no contact, no ball state from here.
/// Holds references; cheap to make per tick.
#include <mujoco/mujoco.h>

#include "control/arm_interface.hpp"
#include "robot/arm_model.hpp"

namespace mg::control {

class MujocoArm final : public ArmBackend {
 public:
  /// `arm` must be built from the mjModel of `d` (robot::ArmModel(m, mount)); both must outlive
  /// the backend.
  MujocoArm(const robot::ArmModel& arm, mjData* d) : arm_(&arm), d_(d) {}
  MeasuredState read() noexcept override;
  void write(const ModuleCommand& command) noexcept override;

 private:
  const robot::ArmModel* arm_;
  mjData* d_;
};

}  // namespace mg::control
