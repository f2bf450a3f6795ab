#include "control/full_system.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "core/rng.hpp"
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
    : world_(&world), model_(&model), d_(d), data_(model), truth_(world, d), perception_(&truth_) {
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

void LockstepRunner::set_perception(perception::Perception* perception) {
  perception_ = perception != nullptr ? perception : &truth_;
}

void LockstepRunner::step() {
  if (steps_ % steps_per_tick_ == 0) {
    if (data_.tick % model_->config().robot_update_divider == 0)
      robot_update(*model_, data_, perception_->perceive(d_->time));
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
  bool touching = false;
  for (int i = 0; i < d->ncon && !touching; ++i) {
    const mjContact& c = d->contact[i];
    touching = (c.geom1 == model.club_geom() && c.geom2 == model.ball_geom()) ||
               (c.geom2 == model.club_geom() && c.geom1 == model.ball_geom());
  }
  if (touching && !r.touching_ball) ++r.club_ball_touches;
  r.touching_ball = touching;
}

// --- Execution noise (FullPuttOptions::torque_noise / placement_noise). Disabled at zero: then
// nothing here touches mjData and the run is bit-identical to a noise-free build.
class TorqueNoise {
 public:
  TorqueNoise(const ModuleModel& model, const mjModel* m, const FullPuttOptions& options)
      : arm_(&model.arm()),
        enabled_(options.torque_noise > 0.0),
        rng_(derive_seed(options.seed, 1)) {
    steps_per_tick_ = std::max(
        1, static_cast<int>(std::lround(model.config().core_period() / m->opt.timestep)));
    for (int j = 0; j < 7; ++j) std_[j] = options.torque_noise * arm_->torque_limit()[j];
  }
  /// Before physics step `step` of the runner: on a core tick, a fresh draw per joint replaces
  /// the previous one in d->qfrc_applied (added to whatever else is applied there).
  void before_step(long step, mjData* d) {
    if (!enabled_ || step % steps_per_tick_ != 0) return;
    for (int j = 0; j < 7; ++j) {
      const double tau = std_[j] * normal_(rng_);
      d->qfrc_applied[arm_->dof_address(j)] += tau - last_[j];
      last_[j] = tau;
    }
  }

 private:
  const robot::ArmModel* arm_;
  bool enabled_;
  Rng rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  int steps_per_tick_ = 2;
  robot::Vector7 std_ = robot::Vector7::Zero();
  robot::Vector7 last_ = robot::Vector7::Zero();
};

/// The tee, plus a Gaussian error of std `placement_noise` per axis (seeded stream 0).
std::array<double, 2> noisy_ball_start(const sim::World& world, const FullPuttOptions& options) {
  std::array<double, 2> xy = world.field().tee;
  if (!(options.placement_noise > 0.0)) return xy;
  Rng rng(derive_seed(options.seed, 0));
  std::normal_distribution<double> normal(0.0, options.placement_noise);
  xy[0] += normal(rng);
  xy[1] += normal(rng);
  return xy;
}

}  // namespace

FullPuttResult full_system_putt(const sim::World& world, const ModuleModel& model, mjData* d,
                                std::array<double, 2> hole, double angle, double speed,
                                const FullPuttOptions& options) {
  world.reset(d);
  world.set_hole(d, hole);
  const std::array<double, 2> ball_start = noisy_ball_start(world, options);
  if (options.placement_noise > 0.0) world.place_ball(d, ball_start);
  robot::Vector7 rest;
  for (int j = 0; j < 7; ++j) rest[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  robot::set_joint_positions(model.arm(), d, rest);
  mj_forward(world.model(), d);

  FullPuttResult r;
  r.ball_start = ball_start;
  r.min_position_margin = 1e9;
  LockstepRunner run(world, model, d);
  TorqueNoise torque_noise(model, world.model(), options);
  const auto step = [&] {
    torque_noise.before_step(run.steps(), d);
    run.step();
  };
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
    step();
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
  const bool request_valid = request_hit(model, run.module(), angle, speed);
  const long hit_steps = std::lround(options.hit_timeout / dt);
  double t_request = d->time;
  bool contact = false;
  // The face velocity before the step in which the club meets the ball: the impact velocity
  // (after that step the contact spring has already slowed the club).
  const auto face_velocity = [&] {
    Eigen::Isometry3d pose;
    robot::Matrix67 jac;
    const robot::Vector7 q = robot::joint_positions(model.arm(), d);
    robot::dh_club_jacobian(model.arm(), q, pose, jac);
    return Eigen::Vector3d(jac.topRows<3>() * robot::joint_velocities(model.arm(), d));
  };
  Eigen::Vector3d club_velocity = Eigen::Vector3d::Zero();
  for (long k = 0; k < hit_steps && !contact; ++k) {
    club_velocity = face_velocity();
    step();
    track_ratios(model, d, run.module(), r);
    if (k == 2 && run.module().state != ModuleState::kHitting) {
      // Execution noise only: the torque disturbance makes the arm jitter around the
      // stationarity threshold, so a valid request can be refused as "not at rest" at the next
      // tick. Wait for the rest pose again and repeat the request, until settle_timeout.
      if (options.torque_noise > 0.0 && request_valid &&
          run.module().state == ModuleState::kRest) {
        bool again = false;
        while (!again && d->time < options.settle_timeout) {
          step();
          track_ratios(model, d, run.module(), r);
          again = run.module().state == ModuleState::kRest && run.module().at_rest_pose &&
                  run.steps() % 2 == 0;
        }
        if (again) {
          request_hit(model, run.module(), angle, speed);
          r.rest_time = t_request = d->time;
          k = -1;
          continue;
        }
      }
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
  r.club = {std::atan2(club_velocity.y(), club_velocity.x()), club_velocity.norm()};

  // The ball rolls; the module brakes and idles meanwhile.
  sim::OutcomeTracker tracker(world, d, options.rules);
  const long launch_step = std::lround(options.launch_delay / dt);
  const long max_steps = std::lround(options.max_duration / dt);
  bool decided = false;
  const double t_contact = d->time;
  long k = 1;
  for (; k <= max_steps && !decided; ++k) {
    step();
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
