#include "sim_backend/simulator_perception.hpp"

namespace mg::perception {

Perceived SimulatorPerception::perceive(double /*now*/) noexcept {
  Perceived p;
  const mjtNum* q = data_->qpos + world_->ids().ball_qpos;
  p.ball = {q[0], q[1], q[2]};
  const auto hole = world_->hole_position(data_);
  // The vision system reports the hole centre on the surface, so this does the same.
  p.hole = {hole[0], hole[1], world_->field().height(hole[0], hole[1])};
  p.age = 0.0;
  p.fresh = true;
  return p;
}

}  // namespace mg::perception
