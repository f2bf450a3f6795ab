// The parts of a full-system putt other than its flow (sim_backend/full_system_parts.hpp).
#include "sim_backend/full_system_parts.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "robot/wam_model.hpp"

namespace mg::control {

void track_ratios(const ModuleModel& model, const SimIds& ids, const mjData* d,
                  const ModuleData& data, FullPuttResult& r) {
  const auto& arm = model.arm();
  const robot::Vector7 q = robot::joint_positions(ids.arm, d);
  const robot::Vector7 qd = robot::joint_velocities(ids.arm, d);
  for (int j = 0; j < 7; ++j) {
    const double lim = arm.torque_limit()[j];
    r.max_torque_ratio = std::max(
        r.max_torque_ratio, std::abs(d->ctrl[ids.arm.actuator[static_cast<std::size_t>(j)]]) / lim);
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
    touching = (c.geom1 == ids.club_geom && c.geom2 == ids.ball_geom) ||
               (c.geom2 == ids.club_geom && c.geom1 == ids.ball_geom);
  }
  if (touching && !r.touching_ball) ++r.club_ball_touches;
  r.touching_ball = touching;
}

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

namespace {

bool same_ids(const sim::WorldIds& a, const sim::WorldIds& b) {
  return a.ball_body == b.ball_body && a.ball_geom == b.ball_geom && a.ball_qpos == b.ball_qpos &&
         a.ball_dof == b.ball_dof && a.ground_geom == b.ground_geom &&
         a.ground_mocap == b.ground_mocap && a.surface_geom == b.surface_geom &&
         a.hole_mocap == b.hole_mocap && a.first_wall_mocap == b.first_wall_mocap &&
         a.hole_floor_geom == b.hole_floor_geom && a.first_wall_geom == b.first_wall_geom;
}

}  // namespace

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

/// The ball at `start`, at rest in its ground contact: settled in `settle_world` (the ball world,
/// else `world` with the arm held at the default posture, away from the ball).
sim::BallState settled_ball(const sim::World& settle_world, mjData* sd, const robot::ArmIds* arm,
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
      for (int j = 0; j < 7; ++j) sd->qvel[arm->dof[static_cast<std::size_t>(j)]] = 0.0;
    }
    settle_world.step(sd);
  }
  sim::BallState s = settle_world.ball_state(sd);
  s.time = 0.0;
  return s;
}

ApproachKey approach_key(const ModuleModel& model) {
  return ApproachKey{model.config(), model.hitting().x_star()};
}

PuttScratch::Impl::AtRest& PuttScratch::Impl::at_rest_slot() {
  if (at_rest.size() < kAtRestCacheSize) return at_rest.emplace_back();
  AtRest& e = at_rest[next_at_rest];
  next_at_rest = (next_at_rest + 1) % kAtRestCacheSize;
  return e;
}

PuttScratch::PuttScratch() : impl_(std::make_unique<Impl>()) {}
PuttScratch::~PuttScratch() = default;

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

void FullPuttOptions::validate() const {
  // The same bound as a ball-only putt's: simulated time is CPU time, and beyond it a double no
  // longer counts 1 ms steps exactly.
  require_in_range("max_duration", max_duration, 0.01, 600.0);
  require_in_range("settle_timeout", settle_timeout, 0.01, 600.0);
  require_in_range("hit_timeout", hit_timeout, 0.01, 600.0);
  require_in_range("launch_delay", launch_delay, 0.0, 1.0);
  require_in_range("record_interval", record_interval, 0.0, 10.0);
  require_in_range("placement_noise", placement_noise, 0.0, 0.1);
  for (std::size_t i = 0; i < 3; ++i)
    require_in_range(fmt::format("stance.position[{}]", i), stance.position[i], -100.0, 100.0);
  require_in_range("stance.yaw", stance.yaw, -2.0 * robot::kPi, 2.0 * robot::kPi);
}

}  // namespace mg::control
