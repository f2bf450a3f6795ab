#include "sim_backend/full_system.hpp"

#include <algorithm>
#include <cmath>

#include "robot/wam_model.hpp"
#include "sim_backend/full_system_parts.hpp"

namespace mg::control {
namespace {

/// What the phases of one putt share: its inputs, the scratch, and the start they agreed on.
struct Putt {
  const sim::World& world;
  const ModuleModel& model;
  mjData* d;
  std::array<double, 2> hole;
  double angle, speed;
  const FullPuttOptions& options;
  const PlantEffects& effects;
  PuttScratch::Impl& mem;
  const SimIds& ids;
  bool own_scratch;  ///< the scratch lives for this call only (no approach cache then)

  std::array<double, 2> ball_start{};
  bool valid_angle = false, at_rest_start = false, kinematic = false;
  /// The arm does what the simulation says (no torque noise): asked once, from the wrapper.
  bool ideal_arm = true;
  bool plant_vision = false;  ///< the module's vision is late or off (effects.perception)
};

/// One physics step of the loop, noting when the module first saw the hit.
struct Stepper {
  CoreLoop& run;
  mjData* d;
  double t_module_hit = -1.0;  ///< [s] state the module measured when it saw the hit (-1: not yet)
  void operator()() {
    const double t_state = d->time;
    run.step();
    if (t_module_hit < 0.0 && run.module().ball_hit) t_module_hit = t_state;
  }
};

/// Resets the world, places the ball (settled on its start when the approach is not simulated)
/// and the arm (the default posture, or the rest pose of the angle).
void place_ball_and_arm(Putt& p) {
  const sim::World& world = p.world;
  const FullPuttOptions& options = p.options;
  const sim::World* ball_world = options.ball_world;
  world.reset(p.d);
  world.set_hole(p.d, p.hole);
  p.ball_start = noisy_ball_start(world, options);
  if (options.placement_noise > 0.0 || !options.stance.identity())
    world.place_ball(p.d, p.ball_start);
  robot::Vector7 rest;
  for (int j = 0; j < 7; ++j) rest[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  const auto& cfg = p.model.config();
  p.valid_angle = std::isfinite(p.angle) && p.angle >= cfg.angle_min && p.angle <= cfg.angle_max;
  p.at_rest_start = options.rest_start == RestStart::kAtRestPose && p.valid_angle;
  // A plant's arm (torque noise) acts during the approach too: then it is simulated.
  p.kinematic = options.rest_start == RestStart::kKinematicApproach && p.valid_angle && p.ideal_arm;
  if (p.at_rest_start || p.kinematic) {
    // The ball at rest in its contact, as after the approach; the arm at the rest pose.
    const sim::World& settle_world = ball_world != nullptr ? *ball_world : world;
    const sim::BallState* s = p.mem.find(settle_world.instance_id(), p.ball_start, p.hole);
    if (s == nullptr) {
      mjData* sd = ball_world != nullptr ? p.mem.data_for(*ball_world) : p.d;
      p.mem.store(settle_world.instance_id(), p.ball_start, p.hole,
                  settled_ball(settle_world, sd, ball_world != nullptr ? nullptr : &p.ids.arm,
                               p.ball_start, p.hole));
      s = p.mem.find(settle_world.instance_id(), p.ball_start, p.hole);
      if (ball_world == nullptr) {  // the settle ran in d
        world.reset(p.d);
        world.set_hole(p.d, p.hole);
      }
    }
    world.set_ball_state(p.d, *s);
    if (p.at_rest_start) rest = rest_joint_positions(p.model, p.angle);
  }
  robot::set_joint_positions(p.ids.arm, p.d, rest);
  mj_forward(world.model(), p.d);
}

/// The kinematic approach: the module's Rest motion with a plant that follows the reference
/// exactly (its reference does not depend on the measurement in Rest, so it is that of a
/// simulated approach). Returns whether the rest pose was reached; `kinematic_steps` counts the
/// steps not simulated.
bool approach_kinematically(const Putt& p, CoreLoop& run, FullPuttResult& r, long settle_steps,
                            long& kinematic_steps) {
  const robot::ArmIds& arm = p.ids.arm;
  mjData* d = p.d;
  bool settled = false;
  while (!settled && run.steps() < settle_steps) {
    const ModuleData& md = run.module();
    robot::set_joint_positions(arm, d, md.q_ref);
    for (int j = 0; j < 7; ++j) d->qvel[arm.dof[static_cast<std::size_t>(j)]] = md.qd_des[j];
    const long before = run.steps();
    run.tick_without_physics();
    kinematic_steps += run.steps() - before;
    track_ratios(p.model, p.ids, d, run.module(), r);
    settled = md.state == ModuleState::kRest && md.at_rest_pose && md.time_in_state > 0.2;
  }
  const ModuleData& md = run.module();
  robot::set_joint_positions(arm, d, md.q_ref);
  for (int j = 0; j < 7; ++j) d->qvel[arm.dof[static_cast<std::size_t>(j)]] = md.qd_des[j];
  mj_forward(p.world.model(), d);
  return settled;
}

/// Brings the arm to the rest pose of the angle (kinematically, from the approach cache, or
/// simulated) and keeps a simulated approach in the cache. Returns whether it got there.
bool approach(const Putt& p, CoreLoop& run, Stepper& step, FullPuttResult& r,
              long& kinematic_steps) {
  const sim::World& world = p.world;
  const FullPuttOptions& options = p.options;
  const double dt = world.model()->opt.timestep;
  const long settle_steps = std::lround(options.settle_timeout / dt);
  const double min_rest_time = p.at_rest_start ? kAtRestSettleTime : 0.2;
  bool settled = false;
  if (p.kinematic) settled = approach_kinematically(p, run, r, settle_steps, kinematic_steps);
  // Approach cache (kApproach, the arm and vision as simulated): a hit restores the state at the
  // hit request.
  const bool cacheable = options.rest_start == RestStart::kApproach && p.valid_angle &&
                         p.ideal_arm && !p.plant_vision && !p.own_scratch;
  ApproachKey key;
  PuttScratch::Impl::AtRest* cached = nullptr;
  if (cacheable) {
    key = approach_key(p.model);
    for (auto& e : p.mem.at_rest)
      if (e.world == world.instance_id() && e.model == &p.model && e.angle == p.angle &&
          e.settle_timeout == options.settle_timeout && e.start == p.ball_start &&
          e.hole == p.hole && e.key == key)
        cached = &e;
  }
  if (cached != nullptr) {
    mj_copyData(p.d, world.model(), cached->data.get());
    run.restore(*cached->module, cached->steps);
    r = cached->result;
    kinematic_steps = cached->steps;
    settled = true;
  }
  for (long k = 0; k < settle_steps && !settled; ++k) {
    step();
    track_ratios(p.model, p.ids, p.d, run.module(), r);
    // Ask once the module says the rest pose is reached (on a core-tick boundary).
    if (run.module().state == ModuleState::kRest && run.module().at_rest_pose && k % 2 == 1 &&
        run.module().time_in_state > min_rest_time) {
      settled = true;
      break;
    }
  }
  r.rest_time = p.d->time;
  if (cacheable && settled && cached == nullptr) {
    PuttScratch::Impl::AtRest& e = p.mem.at_rest_slot();
    if (!e.data || e.world != world.instance_id()) e.data = world.make_data();
    if (!e.module || e.model != &p.model) e.module = std::make_unique<ModuleData>(p.model);
    e.world = world.instance_id();
    e.model = &p.model;
    e.key = key;
    e.angle = p.angle;
    e.settle_timeout = options.settle_timeout;
    e.start = p.ball_start;
    e.hole = p.hole;
    mj_copyData(e.data.get(), world.model(), p.d);
    *e.module = run.module();
    e.steps = run.steps();
    e.result = r;
  }
  return settled;
}

/// Asks for the hit and steps until the club meets the ball (or the hit is refused or times
/// out). Returns whether it met; `club_velocity` is the face velocity at impact, `t_request` the
/// time of the (last) request.
bool hit(const Putt& p, CoreLoop& run, Stepper& step, FullPuttResult& r,
         Eigen::Vector3d& club_velocity, double& t_request) {
  const FullPuttOptions& options = p.options;
  const auto& cfg = p.model.config();
  mjData* d = p.d;
  // The module is asked for the hit the plant's arm reaches (club speed scale).
  HitRequest asked{p.angle, p.speed};
  if (p.effects.hit != nullptr && !p.effects.hit->ideal()) asked = p.effects.hit->reach(asked, cfg);
  const bool request_valid = request_hit(p.model, run.module(), asked.angle, asked.speed);
  const long hit_steps = std::lround(options.hit_timeout / p.world.model()->opt.timestep);
  t_request = d->time;
  bool contact = false;
  // The face velocity before the step in which the club meets the ball: the impact velocity
  // (after that step the contact spring has already slowed the club).
  const auto face_velocity = [&] {
    Eigen::Isometry3d pose;
    robot::Matrix67 jac;
    const robot::Vector7 q = robot::joint_positions(p.ids.arm, d);
    robot::dh_club_jacobian(p.model.arm(), q, pose, jac);
    return Eigen::Vector3d(jac.topRows<3>() * robot::joint_velocities(p.ids.arm, d));
  };
  const int ball_dof = p.world.ids().ball_dof;
  for (long k = 0; k < hit_steps && !contact; ++k) {
    club_velocity = face_velocity();
    step();
    track_ratios(p.model, p.ids, d, run.module(), r);
    if (k == 2 && run.module().state != ModuleState::kHitting) {
      // A plant's arm only (torque noise): the disturbance makes the arm jitter around the
      // stationarity threshold, so a valid request can be refused as "not at rest" at the next
      // tick. Wait for the rest pose again and repeat the request, until settle_timeout.
      if (!p.ideal_arm && request_valid && run.module().state == ModuleState::kRest) {
        bool again = false;
        while (!again && d->time < options.settle_timeout) {
          step();
          track_ratios(p.model, p.ids, d, run.module(), r);
          again = run.module().state == ModuleState::kRest && run.module().at_rest_pose &&
                  run.steps() % 2 == 0;
        }
        if (again) {
          request_hit(p.model, run.module(), asked.angle, asked.speed);
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
      contact = (c.geom1 == p.ids.club_geom && c.geom2 == p.ids.ball_geom) ||
                (c.geom2 == p.ids.club_geom && c.geom1 == p.ids.ball_geom);
    }
    contact = contact || ball_speed > cfg.ball_moving_speed;
  }
  return contact;
}

/// The ball rolls from the first contact until decided; the module brakes and idles meanwhile.
/// Once the club is clear, the roll goes on in the ball world (hand-off), and back in the arm
/// world should the ball come back towards the club. Fills the outcome, launch and hand-off.
void roll(const Putt& p, CoreLoop& run, Stepper& step, FullPuttResult& r, long kinematic_steps) {
  const sim::World& world = p.world;
  const sim::World* ball_world = p.options.ball_world;
  const FullPuttOptions& options = p.options;
  const auto& cfg = p.model.config();
  mjData* d = p.d;
  const double dt = world.model()->opt.timestep;
  const int ball_dof = world.ids().ball_dof;
  const double t_first_contact = d->time;
  sim::OutcomeTracker tracker(world, d, options.rules);
  const long launch_step = std::lround(options.launch_delay / dt);
  const long max_steps = std::lround(options.max_duration / dt);
  bool decided = false;
  const double t_contact = d->time;
  const double ball_radius = world.field().ball.radius;
  const double club_radius = world.model()->geom_rbound[p.ids.club_geom];
  bool may_hand_off = ball_world != nullptr;
  double came_back_at = -1.0;   // [s] time of the last fallback: no new hand-off until past it
  const mjData* ball_data = d;  // where the ball's final state is
  const long record_every =
      options.record_interval > 0.0 ? std::max(1L, std::lround(options.record_interval / dt)) : 0;
  std::vector<sim::BallSample> trajectory;
  const auto record = [&](const sim::World& w, const mjData* data) {
    const mjtNum* q = data->qpos + w.ids().ball_qpos;
    const mjtNum* v = data->qvel + w.ids().ball_dof;
    trajectory.push_back({data->time - t_contact, q[0], q[1], q[2], v[0], v[1], v[2]});
  };
  if (record_every) record(world, d);
  const LaunchEffect* launch = p.effects.launch;
  bool released = launch == nullptr || launch->ideal();
  long k = 1;
  for (; k <= max_steps && !decided; ++k) {
    step();
    track_ratios(p.model, p.ids, d, run.module(), r);
    if (!released && !r.touching_ball) {
      launch->after_release(world, d);
      released = true;
    }
    decided = tracker.update(d);
    if (record_every && (k % record_every == 0 || decided)) record(world, d);
    if (k == launch_step) {
      const double* bv = d->qvel + ball_dof;
      r.launch = {std::atan2(bv[1], bv[0]), std::hypot(bv[0], bv[1])};
      r.launch_state = world.ball_state(d);
      if (options.stance.yaw != 0.0)
        r.launch.angle = std::remainder(r.launch.angle - options.stance.yaw, 2.0 * robot::kPi);
    }
    if (decided || !may_hand_off || k < launch_step || r.touching_ball || d->time <= came_back_at)
      continue;
    const ModuleData& md = run.module();
    if (md.state != ModuleState::kBraking && md.state != ModuleState::kIdle) continue;
    // How far the club can still go: the rest of the braking ramp (bounded by all of it) and
    // the lift, plus tracking error; idle, it holds still.
    const double reach = (md.state == ModuleState::kBraking
                              ? md.v_brake0.norm() * cfg.brake_time + cfg.brake_lift_height
                              : 0.0) +
                         kClubReachMargin;
    const double fallback_radius = reach + club_radius + ball_radius;
    const Eigen::Vector3d club(d->geom_xpos + 3 * p.ids.club_geom);
    const Eigen::Vector3d ball(d->qpos + world.ids().ball_qpos);
    if ((ball - club).norm() < fallback_radius + kHandoffHysteresis) continue;

    // Hand-off: the roll goes on in the ball world; `d` and the tracker stay as they are, to go
    // on from here should the ball come back towards the club.
    mjData* bd = p.mem.data_for(*ball_world);
    ball_world->reset(bd);
    ball_world->set_hole(bd, p.hole);
    ball_world->set_ball_state(bd, world.ball_state(d));
    const sim::OutcomeTracker tracker_at_handoff = tracker;
    const std::size_t samples_at_handoff = trajectory.size();
    const double t_handoff = d->time;
    const int qb = ball_world->ids().ball_qpos;
    long kb = k + 1;
    bool came_back = false;
    for (; kb <= max_steps && !decided; ++kb) {
      ball_world->step(bd);
      decided = tracker.update(bd);
      if (record_every && (kb % record_every == 0 || decided)) record(*ball_world, bd);
      const Eigen::Vector3d b(bd->qpos + qb);
      if (!decided && (b - club).norm() < fallback_radius) {
        came_back = true;
        came_back_at = bd->time;
        break;
      }
    }
    if (!came_back) {
      r.handed_off = true;
      r.handoff_time = t_handoff - t_contact;
      ball_data = bd;
      k = kb;
      break;
    }
    ++r.handoff_fallbacks;
    tracker = tracker_at_handoff;
    trajectory.resize(samples_at_handoff);
    decided = false;
    // Hand off again once past the time the ball came back, when it is clear again.
    may_hand_off = r.handoff_fallbacks < kMaxHandoffFallbacks;
  }
  r.arm_steps = run.steps() - kinematic_steps;
  if (ball_data != d) {
    // `d`: the arm as at the hand-off, the ball as at the end.
    world.set_ball_state(d, ball_world->ball_state(ball_data));
    mj_forward(world.model(), d);
  }
  if (step.t_module_hit >= 0.0) r.hit_detection_lag = step.t_module_hit - t_first_contact;
  r.outcome = tracker.outcome();
  r.outcome.trajectory = std::move(trajectory);
  // The ball's time starts at the first contact (ball-only putts start at the launch).
  r.outcome.duration = ball_data->time - t_contact;
  r.outcome.steps = static_cast<int>(k - 1);
}

}  // namespace

FullPuttResult full_system_putt(const sim::World& world, const ModuleModel& model, mjData* d,
                                std::array<double, 2> hole, double angle, double speed,
                                const FullPuttOptions& options, PuttScratch* scratch,
                                const PlantEffects& effects) {
  if (options.ball_world != nullptr) check_ball_world(world, *options.ball_world);
  options.validate();
  check_stance(world, model, options.stance);
  std::unique_ptr<PuttScratch> local;
  if (scratch == nullptr) {
    local = std::make_unique<PuttScratch>();
    scratch = local.get();
  }
  PuttScratch::Impl& mem = scratch->impl();
  const SimIds& ids = mem.ids_for(world);
  Putt p{world, model, d, hole, angle, speed, options, effects, mem, ids, local != nullptr};
  p.ideal_arm = effects.ideal_arm();
  p.plant_vision = !effects.ideal_perception();
  place_ball_and_arm(p);

  FullPuttResult r;
  r.ball_start = p.ball_start;
  r.min_position_margin = 1e9;
  CoreLoop run(world, p.ids, model, d);
  // The plant's vision (late, off by this putt's error) around what the module sees; the
  // identity wrappers are left out.
  perception::SimulatorPerception truth(world, d);
  perception::Perception& seen = options.perception_source != nullptr
                                     ? options.perception_source->attach(world, d)
                                     : static_cast<perception::Perception&>(truth);
  perception::Perception* vision = &seen;
  for (perception::PerceptionWrapper* w : effects.perception) {
    if (w == nullptr || w->identity()) continue;
    w->wrap(*vision);
    vision = w;
  }
  perception::StancePerception from_stance(*vision, options.stance);
  if (!options.stance.identity())
    run.set_perception(&from_stance);
  else if (p.plant_vision || options.perception_source != nullptr)
    run.set_perception(vision);
  // The plant's arm (torque noise) around the simulated one.
  if (!p.ideal_arm) {
    effects.arm->wrap(run.simulated_arm());
    run.set_arm(effects.arm);
  }
  Stepper step{run, d};
  long kinematic_steps = 0;  // steps not simulated here: kinematic approach or restored
  const auto stopped = [&] {
    r.timing = run.timing();
    r.arm_steps = run.steps() - kinematic_steps;
    return r;
  };

  if (!request_rest(model, run.module(), angle)) {
    r.hit_refused = true;
    return stopped();
  }
  if (!approach(p, run, step, r, kinematic_steps)) return stopped();
  Eigen::Vector3d club_velocity = Eigen::Vector3d::Zero();
  double t_request = 0.0;
  if (!hit(p, run, step, r, club_velocity, t_request)) return stopped();
  r.hit = true;
  r.hit_time = d->time - t_request;
  r.club = {std::atan2(club_velocity.y(), club_velocity.x()), club_velocity.norm()};
  roll(p, run, step, r, kinematic_steps);
  r.timing = run.timing();
  return r;
}

}  // namespace mg::control
