// The true world's effects as wrappers (sim_backend/plant_effects.hpp).
#include "sim_backend/plant_effects.hpp"

#include <algorithm>
#include <cmath>

#include "core/check.hpp"

namespace mg::control {

TorqueNoiseArm::TorqueNoiseArm(const robot::ArmModel& arm, double fraction, std::uint64_t seed)
    : fraction_(fraction), seed_(seed), rng_(seed) {
  require_in_range("torque_noise", fraction, 0.0, 1.0);
  for (int j = 0; j < 7; ++j) std_[j] = fraction * arm.torque_limit()[j];
}

void TorqueNoiseArm::wrap(MujocoArm& arm) noexcept {
  arm_ = &arm;
  rng_.seed(seed_);
  normal_.reset();
  last_.setZero();
}

void TorqueNoiseArm::write(const ModuleCommand& command) noexcept {
  arm_->write(command);
  // A fresh draw replaces the previous one in qfrc_applied (added to whatever else is applied
  // there): the disturbance holds for the core period, as the command does.
  mjData* d = arm_->data();
  const robot::ArmIds& ids = arm_->ids();
  for (int j = 0; j < 7; ++j) {
    const double tau = std_[j] * normal_(rng_);
    d->qfrc_applied[ids.dof[static_cast<std::size_t>(j)]] += tau - last_[j];
    last_[j] = tau;
  }
}

ClubSpeedScale::ClubSpeedScale(double scale) : scale_(scale) {
  require_in_range("club_speed_scale", scale, 0.1, 10.0);
}

HitRequest ClubSpeedScale::reach(const HitRequest& asked, const ControllerConfig& config) const {
  if (scale_ == 1.0) return asked;
  return {asked.angle, std::clamp(asked.speed * scale_, config.speed_min, config.speed_max)};
}

LaunchAngleBias::LaunchAngleBias(double angle) : angle_(angle) {
  require_in_range("launch_angle_bias", angle, -0.5, 0.5);
}

void LaunchAngleBias::after_release(const sim::World& world, mjData* d) const noexcept {
  if (angle_ == 0.0) return;
  const double c = std::cos(angle_), s = std::sin(angle_);
  mjtNum* v = d->qvel + world.ids().ball_dof;
  const double vx = v[0], vy = v[1];
  v[0] = c * vx - s * vy;
  v[1] = s * vx + c * vy;
  mjtNum* q = d->qpos + world.ids().ball_qpos + 3;
  const mjtNum turn[4] = {std::cos(0.5 * angle_), 0.0, 0.0, std::sin(0.5 * angle_)};
  mjtNum turned[4];
  mju_mulQuat(turned, turn, q);
  mju_normalize4(turned);
  for (int i = 0; i < 4; ++i) q[i] = turned[i];
}

bool PlantEffects::ideal_perception() const noexcept {
  for (const perception::PerceptionWrapper* w : perception)
    if (w != nullptr && !w->identity()) return false;
  return true;
}

void PlantEffectValues::validate() const {
  require_in_range("torque_noise", torque_noise, 0.0, 1.0);
  require_in_range("club_speed_scale", club_speed_scale, 0.1, 10.0);
  require_in_range("launch_angle_bias", launch_angle_bias, -0.5, 0.5);
  require_in_range("perception_latency", perception_latency, 0.0, 1.0);
  require_in_range("perceived_ball_offset.x", perceived_ball_offset[0], -1.0, 1.0);
  require_in_range("perceived_ball_offset.y", perceived_ball_offset[1], -1.0, 1.0);
}

PlantWrappers::PlantWrappers(const ModuleModel& model, const PlantEffectValues& values,
                             std::uint64_t seed)
    : noise_((values.validate(), model.arm()), values.torque_noise, derive_seed(seed, 1)),
      speed_(values.club_speed_scale),
      bias_(values.launch_angle_bias),
      late_(values.perception_latency),
      off_(values.perceived_ball_offset) {}

PlantEffects PlantWrappers::effects() {
  PlantEffects e;
  e.arm = &noise_;
  e.hit = &speed_;
  e.launch = &bias_;
  e.perception = {&late_, &off_};
  return e;
}

}  // namespace mg::control
