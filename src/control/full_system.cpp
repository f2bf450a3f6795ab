#include "control/full_system.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"

#include "core/rng.hpp"
#include "robot/wam_model.hpp"

namespace mg::control {

sim::World make_world_with_arm(field::Field field, const robot::WamMount& mount,
                               sim::WorldOptions options) {
  options.extra_worldbody_mjcf = robot::wam_bodies_mjcf(mount);
  options.extra_actuator_mjcf = robot::wam_actuators_mjcf();
  // Only the club head touches anything (the ball); the rest of the arm is drawn only.
  options.extra_bodies_off_static = {"wam_base",  "wam_link1", "wam_link2",
                                     "wam_link3", "wam_link4", "wam_link5",
                                     "wam_link6", "wam_link7", "wam_club"};
  options.extra_bodies_off_ball = {"wam_base",  "wam_link1", "wam_link2", "wam_link3",
                                   "wam_link4", "wam_link5", "wam_link6", "wam_link7"};
  return sim::World(std::move(field), options);
}

ModuleModel make_module_model(const sim::World& world, ds::HittingModel hitting,
                              const ModuleConfig& config, const robot::WamMount& mount) {
  return ModuleModel(world.model(), mount, std::move(hitting), config, world.ids().ball_geom,
                     world.ids().ball_dof);
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
    r.max_velocity_ratio =
        std::max(r.max_velocity_ratio, std::abs(qd[j]) / arm.velocity_limit()[j]);
    r.max_command_velocity_ratio =
        std::max(r.max_command_velocity_ratio, std::abs(data.qd_des[j]) / arm.velocity_limit()[j]);
    r.min_position_margin =
        std::min(r.min_position_margin,
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
/// A hook of the putt's core loop: before each physics step on a core tick, a fresh draw per
/// joint replaces the previous one in d->qfrc_applied (added to whatever else is applied there).
/// The module never reads qfrc_applied, so drawing after the tick's write is the same as before.
class TorqueNoise final : public CoreHooks {
 public:
  TorqueNoise(const ModuleModel& model, const CoreLoop& loop, const FullPuttOptions& options)
      : arm_(&model.arm()),
        d_(loop.data()),
        enabled_(options.torque_noise > 0.0),
        rng_(derive_seed(options.seed, 1)),
        steps_per_tick_(loop.steps_per_tick()) {
    for (int j = 0; j < 7; ++j) std_[j] = options.torque_noise * arm_->torque_limit()[j];
  }
  bool enabled() const { return enabled_; }
  void before_step(long step) override {
    if (!enabled_ || step % steps_per_tick_ != 0) return;
    for (int j = 0; j < 7; ++j) {
      const double tau = std_[j] * normal_(rng_);
      d_->qfrc_applied[arm_->dof_address(j)] += tau - last_[j];
      last_[j] = tau;
    }
  }

 private:
  const robot::ArmModel* arm_;
  mjData* d_;
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
  if (!options.stance.identity()) xy = {options.stance.position[0], options.stance.position[1]};
  if (!(options.placement_noise > 0.0)) return xy;
  Rng rng(derive_seed(options.seed, 0));
  std::normal_distribution<double> normal(0.0, options.placement_noise);
  xy[0] += normal(rng);
  xy[1] += normal(rng);
  return xy;
}

constexpr double kBallSettleTime = 0.3;    // [s] ball at rest in its contact (time constant 0.02 s)
constexpr double kClubReachMargin = 0.05;  // [m] tracking error, idle drift
constexpr double kHandoffHysteresis = 0.05;  // [m] hand-off this much beyond the fallback radius
constexpr int kMaxHandoffFallbacks = 3;
constexpr std::size_t kSettledCacheSize = 8;

bool same_ids(const sim::WorldIds& a, const sim::WorldIds& b) {
  return a.ball_body == b.ball_body && a.ball_geom == b.ball_geom && a.ball_qpos == b.ball_qpos &&
         a.ball_dof == b.ball_dof && a.ground_geom == b.ground_geom &&
         a.ground_mocap == b.ground_mocap && a.surface_geom == b.surface_geom &&
         a.hole_mocap == b.hole_mocap && a.first_wall_mocap == b.first_wall_mocap &&
         a.hole_floor_geom == b.hole_floor_geom && a.first_wall_geom == b.first_wall_geom;
}

/// The ball world must be the arm world without the arm: same field and options, and the same
/// indices for everything but the arm (the outcome tracker reads either data with the arm
/// world's indices).
void check_ball_world(const sim::World& world, const sim::World& ball) {
  const auto& a = world.options();
  const auto& b = ball.options();
  const bool ok =
      same_ids(world.ids(), ball.ids()) && world.field().name == ball.field().name &&
      a.ground == b.ground && a.timestep == b.timestep && a.hole_segments == b.hole_segments &&
      a.cup == b.cup && a.resistance_smoothing == b.resistance_smoothing &&
      a.cup_restitution == b.cup_restitution && a.rolling_slip_limit == b.rolling_slip_limit &&
      a.ground_time_constant == b.ground_time_constant && b.extra_worldbody_mjcf.empty() &&
      world.model()->nuserdata == ball.model()->nuserdata;
  if (!ok)
    throw InputError(
        fmt::format("options.ball_world: expected a ball-only world of field '{}' with "
                    "the arm world's options (make_ball_world), got field '{}'",
                    world.field().name, ball.field().name));
}

/// The arm of `world` must stand where `stance` puts the module's mount: else the module's
/// frame and the simulated arm disagree and it would hit beside the ball.
void check_stance(const sim::World& world, const ModuleModel& model, const robot::Stance& stance) {
  const int base = mj_name2id(world.model(), mjOBJ_BODY, "wam_base");
  if (base < 0) return;  // checked by the module model's construction
  const robot::WamMount expected = robot::mount_at(model.arm().mount(), stance);
  const mjtNum* pos = world.model()->body_pos + 3 * base;
  const mjtNum* q = world.model()->body_quat + 4 * base;
  const double yaw = 2.0 * std::atan2(q[3], q[0]);  // a rotation about z only
  const double dyaw = std::remainder(yaw - expected.base_yaw, 2.0 * robot::kPi);
  bool ok = std::abs(dyaw) < 1e-9;
  for (int i = 0; i < 3; ++i)
    ok = ok && std::abs(pos[i] - expected.base_position[static_cast<std::size_t>(i)]) < 1e-9;
  if (!ok)
    throw InputError(fmt::format(
        "options.stance: the world's arm stands at ({:.3f}, {:.3f}, {:.3f}) yaw {:.3f}, expected "
        "({:.3f}, {:.3f}, {:.3f}) yaw {:.3f} (build the world with mount_at(mount, stance))",
        pos[0], pos[1], pos[2], yaw, expected.base_position[0], expected.base_position[1],
        expected.base_position[2], expected.base_yaw));
}

}  // namespace

struct PuttScratch::Impl {
  // mjData of a ball world; remade when another world is used.
  sim::DataPtr ball_data;
  std::uint64_t ball_data_world = 0;
  // Settled balls: a deterministic function of (settle world, start, hole), so a hit gives the
  // bits of settling anew.
  struct Settled {
    std::uint64_t world = 0;
    std::array<double, 2> start{}, hole{};
    sim::BallState state;
  };
  std::vector<Settled> settled;
  std::size_t next_slot = 0;

  // Arm and ball at the hit request after a simulated approach (RestStart::kApproach), by
  // everything the approach depends on: a hit continues with exactly the bits of the approach.
  struct AtRest {
    std::uint64_t world = 0;
    const ModuleModel* model = nullptr;
    std::vector<double> fingerprint;
    double angle = 0.0, settle_timeout = 0.0;
    std::array<double, 2> start{}, hole{};
    sim::DataPtr data;
    std::unique_ptr<ModuleData> module;
    long steps = 0;
    FullPuttResult result;  // the bookkeeping of the approach
  };
  std::vector<AtRest> at_rest;
  std::size_t next_at_rest = 0;

  AtRest& at_rest_slot();

  mjData* data_for(const sim::World& w) {
    if (!ball_data || ball_data_world != w.instance_id()) {
      ball_data = w.make_data();
      ball_data_world = w.instance_id();
    }
    return ball_data.get();
  }
  const sim::BallState* find(std::uint64_t w, std::array<double, 2> start,
                             std::array<double, 2> hole) const {
    for (const auto& s : settled)
      if (s.world == w && s.start == start && s.hole == hole) return &s.state;
    return nullptr;
  }
  void store(std::uint64_t w, std::array<double, 2> start, std::array<double, 2> hole,
             const sim::BallState& state) {
    if (settled.size() < kSettledCacheSize) {
      settled.push_back({w, start, hole, state});
    } else {
      settled[next_slot] = {w, start, hole, state};
      next_slot = (next_slot + 1) % kSettledCacheSize;
    }
  }
};

namespace {

constexpr std::size_t kAtRestCacheSize = 4;

// What of a module model the approach depends on: a replaced model at the same address does not
// hit the cache.
std::vector<double> approach_fingerprint(const ModuleModel& model) {
  const auto& c = model.config();
  std::vector<double> f{static_cast<double>(c.mode),
                        c.core_rate,
                        static_cast<double>(c.robot_update_divider),
                        c.integral_limit,
                        static_cast<double>(c.fir_length),
                        c.angle_min,
                        c.angle_max,
                        c.club_face_offset,
                        c.rest_speed,
                        c.rest_turn_rate,
                        c.rest_tolerance,
                        c.rest_heading_tolerance,
                        c.stationary_threshold,
                        c.brake_time,
                        c.velocity_fault_factor,
                        c.perception_max_age,
                        c.ball_tolerance,
                        model.rest_speed(),
                        model.rest_turn_rate(),
                        model.ik().damping,
                        model.ik().position_gain,
                        model.ik().orientation_gain,
                        model.ik().posture_gain,
                        model.ik().limit_margin,
                        model.ik().dt,
                        model.ik().velocity_scale};
  for (int j = 0; j < 7; ++j) {
    const auto i = static_cast<std::size_t>(j);
    f.insert(f.end(), {c.kp[i], c.ki[i], c.kd[i], model.posture()[j]});
  }
  f.insert(f.end(), c.rest_offset.begin(), c.rest_offset.end());
  const Eigen::Vector3d& x = model.hitting().x_star();
  f.insert(f.end(), {x.x(), x.y(), x.z()});
  return f;
}

}  // namespace

PuttScratch::Impl::AtRest& PuttScratch::Impl::at_rest_slot() {
  if (at_rest.size() < kAtRestCacheSize) return at_rest.emplace_back();
  AtRest& e = at_rest[next_at_rest];
  next_at_rest = (next_at_rest + 1) % kAtRestCacheSize;
  return e;
}

PuttScratch::PuttScratch() : impl_(std::make_unique<Impl>()) {}
PuttScratch::~PuttScratch() = default;

sim::World make_ball_world(const sim::World& arm_world) {
  sim::WorldOptions o = arm_world.options();
  o.extra_worldbody_mjcf.clear();
  o.extra_actuator_mjcf.clear();
  o.extra_bodies_off_static.clear();
  o.extra_bodies_off_ball.clear();
  return sim::World(arm_world.field(), o);
}

robot::Vector7 rest_joint_positions(const ModuleModel& model, double angle) {
  robot::FaceTarget target;
  target.position = rest_face_position(model, angle);
  target.heading = angle;
  // The controller's IK with a 20x longer step: the same fixed point (qd = 0 does not depend on
  // dt), reached in a few hundred iterations instead of thousands.
  robot::IkOptions ik = model.ik();
  ik.dt *= 20.0;
  robot::Vector7 q;
  for (int j = 0; j < 7; ++j) q[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  robot::Vector7 qd;
  for (int it = 0; it < 3000; ++it) {
    if (robot::track_face(model.arm(), q, target, model.posture(), ik, qd) ==
        robot::RtStatus::kInvalidInput)
      break;
    q += ik.dt * qd;
    if (qd.cwiseAbs().maxCoeff() * ik.dt < 1e-14) break;
  }
  return q;
}

namespace {

/// The ball at `start`, at rest in its ground contact: settled in `settle_world` (the ball world,
/// else `world` with the arm held at the default posture, away from the ball).
sim::BallState settled_ball(const sim::World& settle_world, mjData* sd, const robot::ArmModel* arm,
                            std::array<double, 2> start, std::array<double, 2> hole) {
  settle_world.reset(sd);
  settle_world.set_hole(sd, hole);
  settle_world.place_ball(sd, start);
  robot::Vector7 rest;
  for (int j = 0; j < 7; ++j) rest[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  const long steps = std::lround(kBallSettleTime / settle_world.model()->opt.timestep);
  for (long k = 0; k < steps; ++k) {
    if (arm != nullptr) {
      robot::set_joint_positions(*arm, sd, rest);
      for (int j = 0; j < 7; ++j) sd->qvel[arm->dof_address(j)] = 0.0;
    }
    settle_world.step(sd);
  }
  sim::BallState s = settle_world.ball_state(sd);
  s.time = 0.0;
  return s;
}

/// Turns the ball's motion about the vertical by `angle` [rad]: its linear velocity, and its
/// orientation (so its body-frame spin turns with it).
void turn_ball(const sim::World& world, mjData* d, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  mjtNum* v = d->qvel + world.ids().ball_dof;
  const double vx = v[0], vy = v[1];
  v[0] = c * vx - s * vy;
  v[1] = s * vx + c * vy;
  mjtNum* q = d->qpos + world.ids().ball_qpos + 3;
  const mjtNum turn[4] = {std::cos(0.5 * angle), 0.0, 0.0, std::sin(0.5 * angle)};
  mjtNum turned[4];
  mju_mulQuat(turned, turn, q);
  mju_normalize4(turned);
  for (int i = 0; i < 4; ++i) q[i] = turned[i];
}

}  // namespace

void FullPuttOptions::validate() const {
  // The same bound as a ball-only putt's: simulated time is CPU time, and beyond it a double no
  // longer counts 1 ms steps exactly.
  require_in_range("max_duration", max_duration, 0.01, 600.0);
  require_in_range("settle_timeout", settle_timeout, 0.01, 600.0);
  require_in_range("hit_timeout", hit_timeout, 0.01, 600.0);
  require_in_range("launch_delay", launch_delay, 0.0, 1.0);
  require_in_range("record_interval", record_interval, 0.0, 10.0);
  require_in_range("torque_noise", torque_noise, 0.0, 1.0);
  require_in_range("placement_noise", placement_noise, 0.0, 0.1);
  require_in_range("launch_angle_bias", launch_angle_bias, -0.5, 0.5);
  require_in_range("club_speed_scale", club_speed_scale, 0.1, 10.0);
  require_in_range("perception_latency", perception_latency, 0.0, 1.0);
  require_in_range("perceived_ball_offset.x", perceived_ball_offset[0], -1.0, 1.0);
  require_in_range("perceived_ball_offset.y", perceived_ball_offset[1], -1.0, 1.0);
  for (std::size_t i = 0; i < 3; ++i)
    require_in_range(fmt::format("stance.position[{}]", i), stance.position[i], -100.0, 100.0);
  require_in_range("stance.yaw", stance.yaw, -2.0 * robot::kPi, 2.0 * robot::kPi);
}

FullPuttResult full_system_putt(const sim::World& world, const ModuleModel& model, mjData* d,
                                std::array<double, 2> hole, double angle, double speed,
                                const FullPuttOptions& options, PuttScratch* scratch) {
  const sim::World* ball_world = options.ball_world;
  if (ball_world != nullptr) check_ball_world(world, *ball_world);
  options.validate();
  check_stance(world, model, options.stance);
  std::unique_ptr<PuttScratch> local;
  if (scratch == nullptr) {
    local = std::make_unique<PuttScratch>();
    scratch = local.get();
  }
  PuttScratch::Impl& mem = scratch->impl();

  world.reset(d);
  world.set_hole(d, hole);
  const std::array<double, 2> ball_start = noisy_ball_start(world, options);
  if (options.placement_noise > 0.0 || !options.stance.identity()) world.place_ball(d, ball_start);
  robot::Vector7 rest;
  for (int j = 0; j < 7; ++j) rest[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  const auto& cfg = model.config();
  const bool valid_angle = std::isfinite(angle) && angle >= cfg.angle_min && angle <= cfg.angle_max;
  const bool at_rest_start = options.rest_start == RestStart::kAtRestPose && valid_angle;
  // Torque noise acts on the arm during the approach too: then it is simulated.
  const bool kinematic = options.rest_start == RestStart::kKinematicApproach && valid_angle &&
                         !(options.torque_noise > 0.0);
  if (at_rest_start || kinematic) {
    // The ball at rest in its contact, as after the approach; the arm at the rest pose.
    const sim::World& settle_world = ball_world != nullptr ? *ball_world : world;
    const sim::BallState* s = mem.find(settle_world.instance_id(), ball_start, hole);
    if (s == nullptr) {
      mjData* sd = ball_world != nullptr ? mem.data_for(*ball_world) : d;
      mem.store(settle_world.instance_id(), ball_start, hole,
                settled_ball(settle_world, sd, ball_world != nullptr ? nullptr : &model.arm(),
                             ball_start, hole));
      s = mem.find(settle_world.instance_id(), ball_start, hole);
      if (ball_world == nullptr) {  // the settle ran in d
        world.reset(d);
        world.set_hole(d, hole);
      }
    }
    world.set_ball_state(d, *s);
    if (at_rest_start) rest = rest_joint_positions(model, angle);
  }
  robot::set_joint_positions(model.arm(), d, rest);
  mj_forward(world.model(), d);

  FullPuttResult r;
  r.ball_start = ball_start;
  r.min_position_margin = 1e9;
  CoreLoop run(world, model, d);
  // The plant's vision: late and off by this putt's error.
  const bool plant_vision = options.perception_latency > 0.0 ||
                            options.perceived_ball_offset[0] != 0.0 ||
                            options.perceived_ball_offset[1] != 0.0;
  perception::SimulatorPerception truth(world, d);
  perception::DelayedPerception delayed(truth, options.perception_latency,
                                        options.perceived_ball_offset);
  perception::StancePerception from_stance(
      plant_vision ? static_cast<perception::Perception&>(delayed) : truth, options.stance);
  if (!options.stance.identity())
    run.set_perception(&from_stance);
  else if (plant_vision)
    run.set_perception(&delayed);
  TorqueNoise torque_noise(model, run, options);
  if (torque_noise.enabled()) run.set_hooks(&torque_noise);
  double t_module_hit = -1.0;  // [s] state the module measured when it saw the hit (-1: not yet)
  const auto step = [&] {
    const double t_state = d->time;
    run.step();
    if (t_module_hit < 0.0 && run.module().ball_hit) t_module_hit = t_state;
  };
  const double dt = world.model()->opt.timestep;
  const int ball_dof = world.ids().ball_dof;

  // Rest: go to the rest pose of this angle and settle.
  if (!request_rest(model, run.module(), angle)) {
    r.hit_refused = true;
    r.timing = run.timing();
    r.arm_steps = run.steps();
    return r;
  }
  const long settle_steps = std::lround(options.settle_timeout / dt);
  const double min_rest_time = at_rest_start ? kAtRestSettleTime : 0.2;
  bool settled = false;
  long kinematic_steps = 0;  // steps not simulated here: kinematic approach or restored
  if (kinematic) {
    // The module's Rest motion with a plant that follows the reference exactly: its reference
    // does not depend on the measurement in Rest, so it is that of a simulated approach.
    const robot::ArmModel& arm = model.arm();
    while (!settled && run.steps() < settle_steps) {
      const ModuleData& md = run.module();
      robot::set_joint_positions(arm, d, md.q_ref);
      for (int j = 0; j < 7; ++j) d->qvel[arm.dof_address(j)] = md.qd_des[j];
      const long before = run.steps();
      run.tick_without_physics();
      kinematic_steps += run.steps() - before;
      track_ratios(model, d, run.module(), r);
      settled = md.state == ModuleState::kRest && md.at_rest_pose && md.time_in_state > 0.2;
    }
    const ModuleData& md = run.module();
    robot::set_joint_positions(arm, d, md.q_ref);
    for (int j = 0; j < 7; ++j) d->qvel[arm.dof_address(j)] = md.qd_des[j];
    mj_forward(world.model(), d);
  }
  // Approach cache (kApproach, no noise): a hit restores the state at the hit request.
  const bool cacheable = options.rest_start == RestStart::kApproach && valid_angle &&
                         !(options.torque_noise > 0.0) && !plant_vision && local == nullptr;
  std::vector<double> fingerprint;
  PuttScratch::Impl::AtRest* cached = nullptr;
  if (cacheable) {
    fingerprint = approach_fingerprint(model);
    for (auto& e : mem.at_rest)
      if (e.world == world.instance_id() && e.model == &model && e.angle == angle &&
          e.settle_timeout == options.settle_timeout && e.start == ball_start && e.hole == hole &&
          e.fingerprint == fingerprint)
        cached = &e;
  }
  if (cached != nullptr) {
    mj_copyData(d, world.model(), cached->data.get());
    run.restore(*cached->module, cached->steps);
    r = cached->result;
    kinematic_steps = cached->steps;
    settled = true;
  }
  for (long k = 0; k < settle_steps && !settled; ++k) {
    step();
    track_ratios(model, d, run.module(), r);
    // Ask once the module says the rest pose is reached (on a core-tick boundary).
    if (run.module().state == ModuleState::kRest && run.module().at_rest_pose && k % 2 == 1 &&
        run.module().time_in_state > min_rest_time) {
      settled = true;
      break;
    }
  }
  r.rest_time = d->time;
  if (cacheable && settled && cached == nullptr) {
    PuttScratch::Impl::AtRest& e = mem.at_rest_slot();
    if (!e.data || e.world != world.instance_id()) e.data = world.make_data();
    if (!e.module || e.model != &model) e.module = std::make_unique<ModuleData>(model);
    e.world = world.instance_id();
    e.model = &model;
    e.fingerprint = fingerprint;
    e.angle = angle;
    e.settle_timeout = options.settle_timeout;
    e.start = ball_start;
    e.hole = hole;
    mj_copyData(e.data.get(), world.model(), d);
    *e.module = run.module();
    e.steps = run.steps();
    e.result = r;
  }
  if (!settled) {
    r.timing = run.timing();
    r.arm_steps = run.steps() - kinematic_steps;
    return r;
  }

  // Hit (the arm of a plant reaches club_speed_scale of what it is asked for).
  const double arm_speed =
      options.club_speed_scale == 1.0
          ? speed
          : std::clamp(speed * options.club_speed_scale, cfg.speed_min, cfg.speed_max);
  const bool request_valid = request_hit(model, run.module(), angle, arm_speed);
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
      if (options.torque_noise > 0.0 && request_valid && run.module().state == ModuleState::kRest) {
        bool again = false;
        while (!again && d->time < options.settle_timeout) {
          step();
          track_ratios(model, d, run.module(), r);
          again = run.module().state == ModuleState::kRest && run.module().at_rest_pose &&
                  run.steps() % 2 == 0;
        }
        if (again) {
          request_hit(model, run.module(), angle, arm_speed);
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
    r.arm_steps = run.steps() - kinematic_steps;
    return r;
  }
  r.hit = true;
  r.hit_time = d->time - t_request;
  const double t_first_contact = d->time;
  r.club = {std::atan2(club_velocity.y(), club_velocity.x()), club_velocity.norm()};

  // The ball rolls; the module brakes and idles meanwhile.
  sim::OutcomeTracker tracker(world, d, options.rules);
  const long launch_step = std::lround(options.launch_delay / dt);
  const long max_steps = std::lround(options.max_duration / dt);
  bool decided = false;
  const double t_contact = d->time;
  const double ball_radius = world.field().ball.radius;
  const double club_radius = world.model()->geom_rbound[model.club_geom()];
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
  bool launch_turned = options.launch_angle_bias == 0.0;
  long k = 1;
  for (; k <= max_steps && !decided; ++k) {
    step();
    track_ratios(model, d, run.module(), r);
    if (!launch_turned && !r.touching_ball) {
      turn_ball(world, d, options.launch_angle_bias);
      launch_turned = true;
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
    const Eigen::Vector3d club(d->geom_xpos + 3 * model.club_geom());
    const Eigen::Vector3d ball(d->qpos + world.ids().ball_qpos);
    if ((ball - club).norm() < fallback_radius + kHandoffHysteresis) continue;

    // Hand-off: the roll goes on in the ball world; `d` and the tracker stay as they are, to go
    // on from here should the ball come back towards the club.
    mjData* bd = mem.data_for(*ball_world);
    ball_world->reset(bd);
    ball_world->set_hole(bd, hole);
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
  if (t_module_hit >= 0.0) r.hit_detection_lag = t_module_hit - t_first_contact;
  r.outcome = tracker.outcome();
  r.outcome.trajectory = std::move(trajectory);
  // The ball's time starts at the first contact (ball-only putts start at the launch).
  r.outcome.duration = ball_data->time - t_contact;
  r.outcome.steps = static_cast<int>(k - 1);
  r.timing = run.timing();
  return r;
}

}  // namespace mg::control
