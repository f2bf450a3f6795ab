#pragma once
/// One place that turns a configuration into a ready minigolf system (docs/architecture.md):
/// the field, the field's world with the WAM and club, the same field's ball-only world, the
/// hitting model and the module model. A `System` is immutable after construction and shared by
/// every thread; each thread owns a `SystemData` (its `mjData`s and scratch). Commands and
/// experiments build a System instead of assembling the world themselves.
#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "control/module_config.hpp"
#include "field/field.hpp"
#include "plant/plant.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"
#include "sim_backend/full_system.hpp"

namespace mg::system {

class System;

/// Makes the perception of one thread's putts on `system` (SystemData::perception): what the
/// module of every full-system putt reads instead of the simulator's truth (e.g. the cameras of
/// vision/camera_perception.hpp, made by the doors above this layer). Called once per SystemData,
/// on the thread that makes it; a source is never shared by threads. Empty: the truth.
using PerceptionFactory =
    std::function<std::unique_ptr<perception::PerceptionSource>(const System& system)>;

/// A relative path that does not exist from the working directory is tried from the repository
/// root (the parent of the data folder), so shipped defaults such as
/// `data/models/hitting-default.json` work from anywhere.
std::filesystem::path resolve_data_path(const std::string& text);

/// The module configuration of a run: the YAML file `config_path` (empty: defaults), then the
/// command line's overrides (`field`, `hitting_model`; empty: keep). The hitting-model path is
/// resolved here, once, for every command. Validated; throws InputError/IoError.
control::ModuleConfig load_config(const std::string& config_path, const std::string& field = "",
                                  const std::string& hitting_model = "");

/// Belief and truth (docs/architecture.md): `field()`, `module()` and `config()` are the robot's
/// knowledge, what the teacher, planner, self-teacher and learners read; the worlds are built from
/// the truth, the field with the plant applied (plant::true_field) and the arm with the plant's
/// friction and club, and arm_putt / ball_putt apply the plant's hole, launch and vision. With an
/// empty plant the worlds are built from the field itself: the same bits as without a plant.
class System {
 public:
  /// Loads the field (config.field) and the hitting model, builds both worlds and the module.
  /// Throws InputError/IoError for a bad configuration or file.
  /// `belief`: the robot's estimate of how the world differs from its field file, in a plant's
  /// keys (docs/belief.md); field() is the field file with it applied. Empty: it believes the
  /// file (the same bits as without one).
  /// `perception`: what the module of its putts perceives (each SystemData makes its own source
  /// with it); empty: the simulator's truth, as before.
  explicit System(const control::ModuleConfig& config, plant::Plant plant = {},
                  plant::Plant belief = {}, PerceptionFactory perception = {});
  /// The same with an already loaded field (config.field is then only a label).
  System(const control::ModuleConfig& config, field::Field field, plant::Plant plant = {},
         plant::Plant belief = {}, PerceptionFactory perception = {});
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  const control::ModuleConfig& config() const { return config_; }
  /// The field as the robot believes it is (its field file, with its belief applied).
  const field::Field& field() const { return belief_; }
  /// The field file as surveyed (the belief and the plant both apply to it).
  const field::Field& survey() const { return survey_; }
  /// What the robot believes of the world beyond its field file (empty: nothing).
  const plant::Plant& belief() const { return belief_plant_; }
  /// The world as it is: the oracle and the world builder may read it, the robot may not.
  const plant::Plant& plant() const { return plant_; }
  /// The lane as it is (the field file with the plant applied): the oracle's, never the robot's.
  const field::Field& truth() const { return truth_; }
  const sim::World& arm_world() const { return *arm_world_; }  ///< true field + WAM + club
  const sim::World& ball_world() const {
    return *ball_world_;
  }  ///< true field only (the arm world's options)
  const control::ModuleModel& module() const { return *module_; }
  /// What the module perceives in this System's putts (empty: the simulator's truth).
  const PerceptionFactory& perception_factory() const { return perception_; }

  /// Throws InputError naming `what` unless (angle, speed) is inside the module's safe envelope.
  void check_request(double angle, double speed, const std::string& what) const;
  /// The speed half of `check_request`.
  void check_speed(double speed, const std::string& what) const;

  /// The arm world with the mobile base at `stance` (the true field, the real arm, mounted at
  /// robot::mount_at(its mount, stance)); for the identity, a copy of arm_world()'s build. For
  /// the world builder (arm_putt), not for the robot's decisions.
  std::unique_ptr<sim::World> make_arm_world_at(const robot::Stance& stance) const;

 private:
  control::ModuleConfig config_;
  field::Field survey_;
  plant::Plant belief_plant_;
  field::Field belief_;
  plant::Plant plant_;
  field::Field truth_;
  std::unique_ptr<sim::World> arm_world_;
  std::unique_ptr<sim::World> ball_world_;
  std::unique_ptr<control::ModuleModel> module_;
  robot::WamMount true_mount_;  ///< the real arm in the robot's frame (the plant's friction, club)
  PerceptionFactory perception_;
};

/// The stance rule (docs/round.md "How a stroke is played", 3. Stand): the base stands beside the
/// ball as it stands beside the tee, its hitting frame turned to `aim` [rad, world]: the robot's
/// frame has the ball at its origin (x, y) and +x along `aim`; the base stands as high above the
/// (believed) ground under the ball as above the ground under the tee. For the field's tee at the
/// origin and aim 0: the identity.
robot::Stance stance_for(const System& system, std::array<double, 2> ball, double aim);

/// The stance of a putt of the ball at `ball` towards `hole` (as `putt --ball` and Python's
/// `System.putt(ball=)` choose it): checked on the lane, facing `aim` [rad, world] or, without
/// one, the hole.
robot::Stance putt_stance(const System& system, std::array<double, 2> ball,
                          std::array<double, 2> hole, std::optional<double> aim);

/// The stance rule for a hit given in world terms (docs/play.md, "Where the ball lies"): the base
/// stands beside the ball facing +x (aim 0, stance_for) whenever the arm reaches the hit from
/// there (the angle in the envelope and the club speed under its cap at that angle: every hit the
/// thesis's fixed arm makes), and otherwise turns to face the hitting direction (hitting angle 0
/// in its frame, the full speed cap). So a learned hit is a world direction and a club speed, and
/// data collected by the fixed arm keep their meaning.
struct HitPose {
  robot::Stance stance;  ///< the identity for the field's tee with aim 0
  double angle = 0.0;    ///< [rad] the hitting angle in the stance's frame
  bool turned = false;   ///< the base turned (the hit is out of the fixed arm's reach)
};
HitPose hit_pose(const System& system, std::array<double, 2> ball, double angle, double speed);

/// True when the arm can make the hit from some stance: the angle is finite and the club speed
/// within speed_min..the module's cap.
bool hit_reachable(const System& system, double angle, double speed);

/// [m/s] An angle-only model's fixed club speed (learned on the surveyed green) as the robot plays
/// it now: the club speed that gives the ball the arrival speed `surveyed_speed` gave there, on the
/// green and with the arm it believes in (belief::equivalent_club_speed). `surveyed_speed` itself
/// without a belief.
double believed_fixed_speed(const System& system, const field::Situation& situation,
                            double surveyed_speed);
/// The same in the world as it is (the oracle's).
double true_fixed_speed(const System& system, const field::Situation& situation,
                        double surveyed_speed);

/// Where a model learned on the survey is asked for its hit when the robot sees `seen`: with the
/// hole where the robot believes it really is (+ its belief's hole offset). `seen` itself
/// without a belief.
field::Situation believed_situation(const System& system, const field::Situation& seen);

/// Per-thread mutable state for putts on one System.
struct SystemData {
  explicit SystemData(const System& system);
  sim::DataPtr arm;                               ///< for full-system putts
  sim::DataPtr ball;                              ///< for ball-only putts
  std::unique_ptr<control::PuttScratch> scratch;  ///< hand-off data, approach cache (bit-neutral)
  /// The arm world of the last non-identity stance and its data (rebuilt when the stance
  /// changes; a world per stance keeps System immutable and shared).
  std::unique_ptr<sim::World> stance_world;
  robot::Stance stance;
  sim::DataPtr stance_arm;
  /// This thread's perception (System::perception_factory; nullptr: the truth): arm_putt hands
  /// it to every putt that names none. Last: released before the worlds it renders.
  std::unique_ptr<perception::PerceptionSource> perception;
};

/// Where the hole really is when the robot sees it at `hole`: + the plant's hole offset and this
/// situation's vision error (plant perception.noise, drawn from the hole's bits: the same
/// situation has the same error in every putt, the oracle's included). `hole` without a plant.
std::array<double, 2> real_hole(const System& system, std::array<double, 2> hole);
/// The same for a plant, before any System of it is built.
std::array<double, 2> real_hole(const plant::Plant& plant, std::array<double, 2> hole);

/// Throws InputError (prefixed `where`, naming the plant file) if the plant puts one of `holes`
/// (where the robot sees them) where no hole may be on `field` (off the lane, in an obstacle, on
/// the tee): checked before a run starts, not found by its first putt there after others ran.
/// Without a plant nothing is checked (the holes are the field's, checked by their readers).
void check_real_holes(const field::Field& field, const plant::Plant& plant,
                      const std::vector<std::array<double, 2>>& holes, std::string_view where);

/// The arm hits the ball (lockstep simulator mode) with the hole seen at `hole` (real_hole is
/// where it is): hitting angle `angle` [rad], club speed `speed` [m/s]; the plant's arm and vision
/// act (the module sees the ball off by this situation's vision error), with the caller's
/// `effects` on top (an experiment's execution noise, a stroke's vision error): torque noises add
/// as independent noises (root of squares, drawn from derive_seed(options.seed, 1)), launch biases,
/// latencies and ball offsets add, speed scales multiply. The wrappers of both are built here
/// (control::PlantWrappers), per putt. The ball lies at
/// options.stance's position, the base beside it (stance_for); the identity stance means the
/// field's tee with aim 0. `angle` and the result's club and launch angles are in the stance's
/// frame (aim + angle in the world). Deterministic. Throws InputError for a bad hole or a ball
/// off the lane.
control::FullPuttResult arm_putt(const System& system, SystemData& data, std::array<double, 2> hole,
                                 double angle, double speed, control::FullPuttOptions options = {},
                                 control::PlantEffectValues effects = {});

/// The arm hits the ball lying at situation.ball towards `angle` [rad, world] at club speed
/// `speed` [m/s], the base placed by hit_pose; the hole seen at situation.hole. The result's club
/// and launch angles are world angles. For a ball on the tee and a hit the fixed arm reaches: the
/// same bits as arm_putt.
control::FullPuttResult arm_hit(const System& system, SystemData& data,
                                const field::Situation& situation, double angle, double speed,
                                control::FullPuttOptions options = {},
                                const control::PlantEffectValues& effects = {});

/// The ball alone, launched from `start` (default: the tee) at `angle` [rad, world], `speed`
/// [m/s] (no spin), the hole seen at `hole` (really at real_hole(system, hole)).
sim::PuttOutcome ball_putt(const System& system, SystemData& data, std::array<double, 2> hole,
                           double angle, double speed, double record_interval = 0.0,
                           std::optional<std::array<double, 2>> start = std::nullopt);

using field::check_ball_position;

}  // namespace mg::system
