#include "sim_backend/mujoco_arm.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "sim_backend/wam_mjcf.hpp"

namespace mg::control {

SimIds find_sim_ids(const sim::World& world) {
  const mjModel* m = world.model();
  SimIds ids;
  ids.arm = robot::find_arm_ids(m);
  ids.club_geom = mj_name2id(m, mjOBJ_GEOM, "club_head");
  if (ids.club_geom < 0) throw InputError("module: the model has no geom 'club_head'");
  ids.ball_geom = world.ids().ball_geom;
  ids.ball_qpos = world.ids().ball_qpos;
  ids.ball_dof = world.ids().ball_dof;
  if (ids.ball_dof < 0 || ids.ball_dof + 6 > m->nv)
    throw InputError(
        fmt::format("module: ball dof: expected 0..{}, got {}", m->nv - 6, ids.ball_dof));
  return ids;
}

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

sim::World make_ball_world(const sim::World& arm_world) {
  sim::WorldOptions o = arm_world.options();
  o.extra_worldbody_mjcf.clear();
  o.extra_actuator_mjcf.clear();
  o.extra_bodies_off_static.clear();
  o.extra_bodies_off_ball.clear();
  return sim::World(arm_world.field(), o);
}

ModuleModel make_module_model(const sim::World& world, ds::HittingModel hitting,
                              const ControllerConfig& config, const robot::WamMount& mount) {
  const mjModel* m = world.model();
  const int ball = world.ids().ball_geom;
  if (ball < 0 || ball >= m->ngeom)
    throw InputError(fmt::format("module: ball geom: expected 0..{}, got {}", m->ngeom - 1, ball));
  if (m->geom_type[ball] != mjGEOM_SPHERE)
    throw InputError(fmt::format("module: ball geom {}: expected a sphere", ball));
  ModuleModel model(robot::arm_model_from_mujoco(m, mount), std::move(hitting), config,
                    m->geom_size[3 * ball]);
  (void)find_sim_ids(world);  // the club head and the ball's joint are there too
  return model;
}

void module_reset(const ModuleModel& model, ModuleData& data, const robot::ArmIds& arm,
                  const mjData* d) {
  module_reset(model, data, robot::joint_positions(arm, d));
}

MeasuredState MujocoArm::read() noexcept {
  MeasuredState s;
  s.time = d_->time;
  s.q = robot::joint_positions(*arm_, d_);
  s.qd = robot::joint_velocities(*arm_, d_);
  return s;
}

void MujocoArm::write(const ModuleCommand& command) noexcept {
  for (int j = 0; j < 7; ++j)
    d_->ctrl[arm_->actuator[static_cast<std::size_t>(j)]] = command.tau[j];
}

void physics_step(const sim::World& world, const SimIds& ids, mjData* d) {
  const mjtNum* club = d->geom_xpos + 3 * ids.club_geom;
  const mjtNum* ball = d->geom_xpos + 3 * ids.ball_geom;
  const double dx = club[0] - ball[0], dy = club[1] - ball[1], dz = club[2] - ball[2];
  if (dx * dx + dy * dy + dz * dz < kImpactZone * kImpactZone)
    world.step_fine(d);
  else
    world.step(d);
}

}  // namespace mg::control
