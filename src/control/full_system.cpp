#include "control/full_system.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "robot/wam_model.hpp"

namespace mg::control {

sim::World make_world_with_arm(field::Field field, const robot::WamMount& mount,
                               sim::WorldOptions options) {
  options.extra_worldbody_mjcf = robot::wam_bodies_mjcf(mount);
  options.extra_actuator_mjcf = robot::wam_actuators_mjcf();
  return sim::World(std::move(field), options);
}

ModuleModel make_module_model(const sim::World& world, ds::HittingModel hitting,
                              const ModuleConfig& config, const robot::WamMount& mount) {
  return ModuleModel(world.model(), mount, std::move(hitting), config, world.ids().ball_geom,
                     world.ids().ball_dof);
}

LockstepRunner::LockstepRunner(const sim::World& world, const ModuleModel& model, mjData* d)
    : world_(&world), model_(&model), d_(d), data_(model) {
  steps_per_tick_ = static_cast<int>(std::lround(model.config().core_period() / world.model()->opt.timestep));
  steps_per_tick_ = std::max(steps_per_tick_, 1);
  durations_us_.reserve(1 << 16);
  module_reset(model, data_, d);
}

void LockstepRunner::reset_module() {
  module_reset(*model_, data_, d_);
  durations_us_.clear();
  steps_ = 0;
}

void LockstepRunner::step() {
  if (steps_ % steps_per_tick_ == 0) {
    const auto t0 = std::chrono::steady_clock::now();
    core_update(*model_, data_, d_);
    const auto t1 = std::chrono::steady_clock::now();
    durations_us_.push_back(
        static_cast<float>(std::chrono::duration<double, std::micro>(t1 - t0).count()));
  }
  world_->step(d_);
  ++steps_;
}

CoreTiming LockstepRunner::timing() const {
  CoreTiming t;
  t.ticks = static_cast<int>(durations_us_.size());
  if (durations_us_.empty()) return t;
  std::vector<float> s = durations_us_;
  std::sort(s.begin(), s.end());
  const std::size_t i99 = std::min(s.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(s.size())));
  t.core_update_p99_us = s[i99];
  t.core_update_max_us = s.back();
  double sum = 0.0;
  const double budget_us = model_->config().core_period() * 1e6;
  for (float v : s) {
    sum += v;
    if (v > budget_us) ++t.overruns;
  }
  t.core_update_mean_us = sum / static_cast<double>(s.size());
  return t;
}

namespace {

void track_ratios(const ModuleModel& model, const mjData* d, const ModuleData& data,
                  FullPuttResult& r) {
  const auto& arm = model.arm();
  const robot::Vector7 q = robot::joint_positions(arm, d);
  const robot::Vector7 qd = robot::joint_velocities(arm, d);
  for (int j = 0; j < 7; ++j) {
    const double lim = arm.torque_limit()[j];
    r.max_torque_ratio = std::max(r.max_torque_ratio, std::abs(d->ctrl[arm.actuator_id(j)]) / lim);
    r.max_raw_torque_ratio = std::max(r.max_raw_torque_ratio, std::abs(data.tau_raw[j]) / lim);
    r.max_velocity_ratio = std::max(r.max_velocity_ratio, std::abs(qd[j]) / arm.velocity_limit()[j]);
    r.max_command_velocity_ratio = std::max(r.max_command_velocity_ratio,
                                            std::abs(data.qd_des[j]) / arm.velocity_limit()[j]);
    r.min_position_margin = std::min(
        r.min_position_margin,
        std::min(q[j] - arm.position_lower()[j], arm.position_upper()[j] - q[j]));
  }
  if (data.last.fault) r.faulted = true;
}

}  // namespace

FullPuttResult full_system_putt(const sim::World& world, const ModuleModel& model, mjData* d,
                                std::array<double, 2> hole, double angle, double speed,
                                const FullPuttOptions& options) {
  world.reset(d);
  world.set_hole(d, hole);
  robot::Vector7 rest;
  for (int j = 0; j < 7; ++j) rest[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  robot::set_joint_positions(model.arm(), d, rest);
  mj_forward(world.model(), d);

  FullPuttResult r;
  r.min_position_margin = 1e9;
  LockstepRunner run(world, model, d);
  const double dt = world.model()->opt.timestep;
  const int ball_dof = world.ids().ball_dof;

  // Rest: go to the rest pose of this angle and settle.
  if (!request_rest(model, run.module(), angle)) {
    r.hit_refused = true;
    r.timing = run.timing();
    return r;
  }
  const long settle_steps = std::lround(options.settle_timeout / dt);
  bool settled = false;
  for (long k = 0; k < settle_steps; ++k) {
    run.step();
    track_ratios(model, d, run.module(), r);
    // Ask once the module says the rest pose is reached (on a core-tick boundary).
    if (run.module().state == ModuleState::kRest && run.module().at_rest_pose && k % 2 == 1 &&
        run.module().time_in_state > 0.2) {
      settled = true;
      break;
    }
  }
  r.rest_time = d->time;
  if (!settled) {
    r.timing = run.timing();
    return r;
  }

  // Hit.
  request_hit(model, run.module(), angle, speed);
  const long hit_steps = std::lround(options.hit_timeout / dt);
  const double t_request = d->time;
  bool contact = false;
  for (long k = 0; k < hit_steps && !contact; ++k) {
    run.step();
    track_ratios(model, d, run.module(), r);
    if (k == 2 && run.module().state != ModuleState::kHitting) {
      r.hit_refused = true;
      break;
    }
    const double* bv = d->qvel + ball_dof;
    const double ball_speed = std::sqrt(bv[0] * bv[0] + bv[1] * bv[1] + bv[2] * bv[2]);
    for (int i = 0; i < d->ncon && !contact; ++i) {
      const mjContact& c = d->contact[i];
      contact = (c.geom1 == model.club_geom() && c.geom2 == model.ball_geom()) ||
                (c.geom2 == model.club_geom() && c.geom1 == model.ball_geom());
    }
    contact = contact || ball_speed > model.config().ball_moving_speed;
  }
  if (!contact) {
    r.timing = run.timing();
    return r;
  }
  r.hit = true;
  r.hit_time = d->time - t_request;
  {
    // Club face velocity from the Jacobian at the measured state.
    Eigen::Isometry3d pose;
    robot::Matrix67 jac;
    const robot::Vector7 q = robot::joint_positions(model.arm(), d);
    robot::dh_club_jacobian(model.arm(), q, pose, jac);
    const Eigen::Vector3d v = jac.topRows<3>() * robot::joint_velocities(model.arm(), d);
    r.club = {std::atan2(v.y(), v.x()), v.norm()};
  }

  // The ball rolls; the module brakes and idles meanwhile.
  sim::OutcomeTracker tracker(world, d, options.rules);
  const long launch_step = std::lround(options.launch_delay / dt);
  const long max_steps = std::lround(options.max_duration / dt);
  bool decided = false;
  const double t_contact = d->time;
  long k = 1;
  for (; k <= max_steps && !decided; ++k) {
    run.step();
    track_ratios(model, d, run.module(), r);
    decided = tracker.update(d);
    if (k == launch_step) {
      const double* bv = d->qvel + ball_dof;
      r.launch = {std::atan2(bv[1], bv[0]), std::hypot(bv[0], bv[1])};
    }
  }
  r.outcome = tracker.outcome();
  // The ball's time starts at the first contact (ball-only putts start at the launch).
  r.outcome.duration = d->time - t_contact;
  r.outcome.steps = static_cast<int>(k - 1);
  r.timing = run.timing();
  return r;
}

}  // namespace mg::control
