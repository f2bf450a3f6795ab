#pragma once
/// The MuJoCo world of one field: heightfield lane, borders, ball and a movable hole.
///
/// Model/data split: a `World` is immutable after construction (it owns the `mjModel` and the
/// field); every simulation run owns its own `mjData` (`World::make_data`). The hole is a mocap
/// body (cup floor and wall segments; WorldOptions::cup), so moving it between putts changes
/// `mjData` only and never re-parses the model.
///
/// Threads: a `World` may be shared by any number of threads, each stepping its own `mjData`;
/// worlds may be constructed concurrently. No process-wide MuJoCo callback is set: contacts come
/// from the model alone (contype/conaffinity, excluded body pairs, predefined geom pairs).
///
/// Ground contact: MuJoCo 2.2.2's heightfield contacts make a rolling ball drift sideways and
/// lose speed (measured: 2-9 cm per metre, 5-17 % speed; docs/physics.md), so the heightfield
/// is drawn but does not collide. The ball touches an exact, analytic surface instead: a mocap
/// box whose top face is moved every step onto the tangent plane at the ball's foot point.
///
/// Ball physics (see docs/physics.md): condim-3 contacts for sliding friction, plus an explicit
/// rolling-resistance torque of magnitude rho r N opposing the ball's rolling (Penner's model),
/// applied before every step. The ground under the hole opening is removed by moving the ground's
/// collision geom (a mocap body) out of reach while the ball's centre is over the opening (a
/// heightfield cannot have a hole), so the ball falls into a geometric cup and lips out or drops
/// as a real ball does.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "field/field.hpp"
#include "sim/mujoco_handles.hpp"
#include "sim/walls.hpp"

namespace mg::sim {

/// What the ball rolls on.
enum class GroundContact {
  kTangentPlane,  ///< exact analytic surface through a moving tangent plane (default)
  kHeightfield,   ///< MuJoCo's heightfield contacts (kept for comparison; docs/physics.md)
};

/// How the cup (floor and wall segments) is made of mocap bodies.
enum class CupBodies {
  /// One body: vertical walls on the hole's tangent plane, tilted with it, lowered so that no wall
  /// top sticks out of the ground (on level ground: kPerSegment's geometry exactly). Collision
  /// costs half of kPerSegment's (MuJoCo's broadphase sorts every pair of overlapping bodies).
  kOne,
  /// A body per wall segment and one for the floor: vertical walls, each top at the lowest
  /// ground along its chord, the floor level (the cup before notes/speed.md).
  kPerSegment,
};

/// Simulation settings shared by every world.
struct WorldOptions {
  GroundContact ground = GroundContact::kTangentPlane;
  double timestep = 0.001;  ///< [s]; PHYSICS.md: at or under 1 ms for a small fast sphere
  int hole_segments = 24;   ///< cup wall made of this many boxes
  CupBodies cup = CupBodies::kOne;
  /// Below this rolling speed the resistance torque is scaled down linearly, so a resting ball
  /// does not chatter (a regularised Coulomb law). [rad/s]
  double resistance_smoothing = 0.05;
  /// Bounce of the ball off the cup's wall (plastic liner) [-].
  double cup_restitution = 0.3;
  /// Rolling resistance acts fully while the contact point slips slower than half this, and
  /// fades out linearly up to it: a sliding ball obeys kinetic friction only. [m/s]
  double rolling_slip_limit = 0.05;
  /// solref time constant of ball-ground contacts [s]. Stiffer contacts make a sliding ball hop
  /// (measured: 11 mm at 2 m/s with 0.002 s, under 0.5 mm with 0.02 s); softer ones sink it
  /// in. See docs/physics.md.
  double ground_time_constant = 0.02;
  /// MJCF inserted into the world's `<worldbody>` and `<actuator>` (the arm, from src/robot; sim
  /// does not depend on robot). Angles in radians. Geoms that should hit the ball use contype 4.
  std::string extra_worldbody_mjcf;
  std::string extra_actuator_mjcf;
  /// Bodies of extra_worldbody_mjcf that never touch the lane, its borders, the ground box or the
  /// cup, and those that never touch the ball either: their pairs are excluded from collision
  /// (MuJoCo 2.2.2 would test them every step; for the arm that was a third of a step).
  std::vector<std::string> extra_bodies_off_static;
  std::vector<std::string> extra_bodies_off_ball;
  void validate() const;
};

/// Indices into the MuJoCo model that the simulation needs.
struct WorldIds {
  int ball_body = -1;
  int ball_geom = -1;
  int ball_qpos = -1;    ///< first of 7 qpos of the ball's free joint
  int ball_dof = -1;     ///< first of 6 dofs
  int ground_geom = -1;  ///< what the ball rolls on: the tangent box or the heightfield
  int ground_mocap = -1;
  int surface_geom = -1;        ///< the heightfield as drawn (never collides)
  int lane_contact_mocap = -1;  ///< kHeightfield: the mocap copy of it that collides (else -1)
  int hole_mocap = -1;          ///< the cup's body (kOne) or the floor's (kPerSegment)
  int hole_floor_geom = -1;
  int first_wall_geom = -1;   ///< cup wall segments are consecutive geoms
  int first_wall_mocap = -1;  ///< kPerSegment: their consecutive bodies (kOne: -1)
};

/// The ball's part of a simulation state: enough to continue the ball's motion in another
/// `mjData` of this world or of another world of the same field (with or without the arm).
struct BallState {
  std::array<mjtNum, 7> qpos{};            ///< free joint: centre [m], orientation (w, x, y, z)
  std::array<mjtNum, 6> qvel{};            ///< [m/s] linear (world); [rad/s] angular (body)
  std::array<mjtNum, 6> qacc_warmstart{};  ///< the constraint solver's warm start
  double ground_normal = 0.0;  ///< [N] last solved ground normal force (rolling resistance)
  double time = 0.0;           ///< [s] simulation time
};

/// Damping ratio of a spring-damper contact (MuJoCo solref's second number) whose bounce has
/// coefficient of restitution `e` (1 for e <= 0: no bounce).
double damping_ratio_for_restitution(double e);

class World {
 public:
  /// Builds the model for `field` (validated). Throws `InputError` for an unusable field.
  explicit World(field::Field field, const WorldOptions& options = {});

  const mjModel* model() const { return model_.get(); }
  const field::Field& field() const { return field_; }
  const WorldOptions& options() const { return options_; }
  const WorldIds& ids() const { return ids_; }
  /// The borders and obstacles the ball bounces off (drawn by MuJoCo, collided by sim/walls).
  const Walls& walls() const { return walls_; }
  /// The generated MJCF text (for debugging and `minigolf field show --mjcf`).
  const std::string& mjcf() const { return mjcf_; }

  /// A fresh `mjData` for this model, hole at the field's default position.
  DataPtr make_data() const;
  /// Resets `d` to the model's initial state: ball on the tee, hole at the field's default.
  void reset(mjData* d) const;

  /// Moves the hole (cup walls, floor, the ground's gap) to `position`. Throws `InputError` if
  /// the hole would leave the lane or sit on ground too steep for its depth.
  void set_hole(mjData* d, std::array<double, 2> position) const;
  /// The hole position currently set in `d`.
  std::array<double, 2> hole_position(const mjData* d) const;

  /// The ball's state in `d`.
  BallState ball_state(const mjData* d) const;
  /// Writes `s` into `d` (ball qpos, qvel, warm start, ground normal force, time) and moves the
  /// ground contact under the ball; other bodies and the hole are left alone. Real-time safe.
  void set_ball_state(mjData* d, const BallState& s) const;

  /// A number unique to this world in the process (caches keyed by a world use it, not its
  /// address, which a later world may reuse).
  std::uint64_t instance_id() const { return instance_id_; }

  /// Puts the ball at rest on the surface at `xy` (centre one radius above the ground).
  void place_ball(mjData* d, std::array<double, 2> xy) const;

  /// One physics step: `mj_step1`, the rolling-resistance torque (ball-ground contact now, normal
  /// force of the last solve), `mj_step2`, then the ball's impacts on borders and obstacles
  /// (resolve_walls; the speed into the face is left in userdata[kUserWallImpact]).
  /// Real-time safe: no allocation, no exceptions.
  void step(mjData* d) const;
  /// The same time (one timestep) in kImpactSubsteps steps of a copy of the model with a
  /// timestep that much shorter. For the club-ball impact: the 8 ms contact resolved at 1 ms made
  /// the launch speed depend on the phase of the step at first touch (launch / club speed
  /// scattered with a std of 0.034 over club speeds 0.01 m/s apart; 0.012 at 0.5 ms).
  void step_fine(mjData* d) const;
  static constexpr int kImpactSubsteps = 4;

  /// [m/s] The speed into a border or obstacle face resolved in the last step of `d` (0: none).
  double wall_impact(const mjData* d) const;

  /// Total normal force of ground contacts on the ball in the current `mjData` [N].
  double ground_normal_force(const mjData* d) const;

  /// Moves the ground contact box so its top face is the surface's tangent plane under the
  /// ball. Real-time safe.
  void update_ground_contact(mjData* d) const;

  /// True for a contact between the ball and what it rolls on (the ground or the cup floor).
  bool is_ball_ground(const mjContact& c) const;

 private:
  field::Field field_;
  WorldOptions options_;
  void set_segmented_cup(mjData* d, std::array<double, 2> position) const;

  void step_with(const mjModel* m, mjData* d) const;
  void resolve_wall_contacts(mjData* d, const std::array<double, 3>& previous) const;

  ModelPtr model_;
  Walls walls_;
  ModelPtr fine_model_;  ///< model_ with timestep / kImpactSubsteps (step_fine)
  std::array<mjtNum, 3> lane_contact_pos_{};  ///< kHeightfield: its body's place [m] (as compiled)
  WorldIds ids_;
  std::string mjcf_;
  std::uint64_t instance_id_ = 0;
};

/// Builds the MJCF text for a field (exposed for tests).
std::string build_world_mjcf(const field::Field& field, const WorldOptions& options);

}  // namespace mg::sim
