#include "control/mujoco_arm.hpp"

namespace mg::control {

MeasuredState MujocoArm::read() noexcept {
  MeasuredState s;
  s.time = d_->time;
  s.q = robot::joint_positions(*arm_, d_);
  s.qd = robot::joint_velocities(*arm_, d_);
  return s;
}

void MujocoArm::write(const ModuleCommand& command) noexcept {
  for (int j = 0; j < 7; ++j) d_->ctrl[arm_->actuator_id(j)] = command.tau[j];
}

}  // namespace mg::control
