#pragma once
/// The MuJoCo adapter of the minigolf module: everything that knows the simulator's ids and reads
/// or writes an mjData for the controller. The controller (control/minigolf_module.hpp and what it
/// includes) never sees MuJoCo; a driver for the real WAM would be another adapter
/// (docs/hardware.md).
///
/// - `MujocoArm`, the arm backend (control/arm_interface.hpp): `read` takes the joint state from
///   the simulation (qpos/qvel at the arm's joints, d->time), `write` puts the torques on the
///   arm's motors (d->ctrl). Only the joints: the module gets no contact, no ball state from here.
/// - `make_module_model`: the module model from a compiled world (the arm's limits, the ball's
///   radius); `module_reset` from a simulation's arm.
/// - the worlds with the arm, and `physics_step` (fine steps near the impact).
#include <mujoco/mujoco.h>

#include "control/arm_interface.hpp"
#include "control/minigolf_module.hpp"
#include "sim/world.hpp"
#include "sim_backend/arm_mujoco.hpp"

namespace mg::control {

/// Where the arm, the club head and the ball are in one compiled world (plain indices).
struct SimIds {
  robot::ArmIds arm;
  int club_geom = -1;  ///< `club_head`
  int ball_geom = -1;
  int ball_qpos = -1;  ///< the ball's free joint: 7 qpos from here
  int ball_dof = -1;   ///< ... and 6 dofs from here
};

/// The ids of a world of make_world_with_arm. Throws InputError naming what is missing.
SimIds find_sim_ids(const sim::World& world);

/// The field's world with the WAM + club inserted (default mount).
sim::World make_world_with_arm(field::Field field, const robot::WamMount& mount = {},
                               sim::WorldOptions options = {});

/// A ball-only world matching `arm_world` (a world of make_world_with_arm): the same field and
/// world options, without the arm. For FullPuttOptions::ball_world.
sim::World make_ball_world(const sim::World& arm_world);

/// The module model for a world built by make_world_with_arm with the same mount: the arm with
/// the compiled model's limits (robot::arm_model_from_mujoco), the ball's radius from its geom.
/// Validates; throws InputError.
ModuleModel make_module_model(const sim::World& world, ds::HittingModel hitting,
                              const ControllerConfig& config, const robot::WamMount& mount = {});

/// Resets the module to Idle with the reference at the arm's joint positions in `d`.
void module_reset(const ModuleModel& model, ModuleData& data, const robot::ArmIds& arm,
                  const mjData* d);

/// The simulator as an arm backend. Holds references; cheap to make per tick. Real-time safe.
class MujocoArm final : public ArmBackend {
 public:
  /// `arm`: the ids of the world `d` belongs to; both must outlive the backend.
  MujocoArm(const robot::ArmIds& arm, mjData* d) : arm_(&arm), d_(d) {}
  MeasuredState read() noexcept override;
  void write(const ModuleCommand& command) noexcept override;
  /// The simulation it reads and writes, for a wrapper that acts on more of it (a plant's arm:
  /// sim_backend/plant_effects.hpp).
  const robot::ArmIds& ids() const { return *arm_; }
  mjData* data() const { return d_; }

 private:
  const robot::ArmIds* arm_;
  mjData* d_;
};

/// [m] Within this distance of the ball centre, the club head's centre is "at the impact": the
/// physics steps in kImpactSubsteps finer steps (sim::World::step_fine) so the launch does not
/// depend on where in a 1 ms step the club first touches the ball.
constexpr double kImpactZone = 0.06;
/// One physics step of a world with the arm: fine near the impact, else the plain step.
/// Real-time safe.
void physics_step(const sim::World& world, const SimIds& ids, mjData* d);

}  // namespace mg::control
