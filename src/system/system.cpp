#include "system/system.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "belief/prior.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/rng.hpp"
#include "ds/hitting_model.hpp"

namespace mg::system {

std::filesystem::path resolve_data_path(const std::string& text) {
  const std::filesystem::path p(text);
  std::error_code ec;
  if (p.is_absolute() || std::filesystem::exists(p, ec)) return p;
  const std::filesystem::path from_root = data_dir().parent_path() / p;
  return std::filesystem::exists(from_root, ec) ? from_root : p;
}

control::ModuleConfig load_config(const std::string& config_path, const std::string& field,
                                  const std::string& hitting_model) {
  control::ModuleConfig config;
  if (!config_path.empty()) {
    std::error_code ec;
    if (std::filesystem::is_directory(config_path, ec))
      throw InputError(
          fmt::format("--config: '{}' is a directory, expected a YAML file", config_path));
    config = control::load_module_config(config_path);
  }
  if (!field.empty()) config.field = field;
  if (!hitting_model.empty()) config.hitting_model = hitting_model;
  config.hitting_model = resolve_data_path(config.hitting_model).string();
  config.validate();
  return config;
}

System::System(const control::ModuleConfig& config, plant::Plant plant, plant::Plant belief,
               PerceptionFactory perception)
    : System(config, field::load_field(config.field), std::move(plant), std::move(belief),
             std::move(perception)) {}

System::System(const control::ModuleConfig& config, field::Field field, plant::Plant plant,
               plant::Plant belief, PerceptionFactory perception)
    : config_(config),
      survey_(std::move(field)),
      belief_plant_(std::move(belief)),
      belief_(plant::true_field(survey_, belief_plant_)),
      plant_(std::move(plant)),
      truth_(plant::true_field(survey_, plant_)),
      perception_(std::move(perception)) {
  config_.validate();
  plant_.validate();
  belief_plant_.validate();
  config_.hitting_model = resolve_data_path(config_.hitting_model).string();
  ds::HittingModel hitting = ds::read_hitting_model(config_.hitting_model);
  // The robot's mount (its model of itself) and the real one: friction and club face.
  const robot::WamMount belief_mount;
  robot::WamMount true_mount = belief_mount;
  true_mount.joint_friction = plant_.arm.joint_friction;
  if (plant_.arm.club_restitution_scale != 1.0)
    true_mount.club.face_restitution =
        std::min(0.99, belief_mount.club.face_restitution * plant_.arm.club_restitution_scale);
  true_mount_ = true_mount;
  arm_world_ = std::make_unique<sim::World>(control::make_world_with_arm(truth_, true_mount));
  ball_world_ = std::make_unique<sim::World>(control::make_ball_world(*arm_world_));
  // The module's model reads the arm's kinematics and inertia (the same in both mounts) and the
  // ball's radius from the world, and the robot's own mount: never the plant.
  module_ = std::make_unique<control::ModuleModel>(
      control::make_module_model(*arm_world_, std::move(hitting), config_, belief_mount));
}

double believed_fixed_speed(const System& system, const field::Situation& situation,
                            double surveyed_speed) {
  return belief::equivalent_club_speed(surveyed_speed, system.survey(), system.field(),
                                       system.belief().arm.club_speed_scale, situation.ball,
                                       situation.hole);
}

double true_fixed_speed(const System& system, const field::Situation& situation,
                        double surveyed_speed) {
  return belief::equivalent_club_speed(surveyed_speed, system.survey(), system.truth(),
                                       system.plant().arm.club_speed_scale, situation.ball,
                                       situation.hole);
}

field::Situation believed_situation(const System& system, const field::Situation& seen) {
  const auto& offset = system.belief().field.hole_offset;
  if (offset[0] == 0.0 && offset[1] == 0.0) return seen;
  return {seen.ball, {seen.hole[0] + offset[0], seen.hole[1] + offset[1]}};
}

void System::check_request(double angle, double speed, const std::string& what) const {
  const auto& c = config_;
  if (!std::isfinite(angle) || angle < c.angle_min || angle > c.angle_max)
    throw InputError(fmt::format("{}: angle: expected {}..{} rad (safe envelope), got {}", what,
                                 c.angle_min, c.angle_max, angle));
  check_speed(speed, what);
}

void System::check_speed(double speed, const std::string& what) const {
  const auto& c = config_;
  if (!std::isfinite(speed) || speed < c.speed_min || speed > c.speed_max)
    throw InputError(
        fmt::format("{}: speed: expected {}..{} m/s (club speed, safe envelope), got {}", what,
                    c.speed_min, c.speed_max, speed));
}

std::unique_ptr<sim::World> System::make_arm_world_at(const robot::Stance& stance) const {
  return std::make_unique<sim::World>(control::make_world_with_arm(
      arm_world_->field(), robot::mount_at(true_mount_, stance), arm_world_->options()));
}

robot::Stance stance_for(const System& system, std::array<double, 2> ball, double aim) {
  robot::Stance s;
  // As high above the ground under the ball as the arm beside the tee stands above the tee's.
  const field::Field& f = system.field();
  s.position = {ball[0], ball[1], f.height(ball[0], ball[1]) - f.height(f.tee[0], f.tee[1])};
  s.yaw = std::remainder(aim, 2.0 * robot::kPi);
  if (s.position[2] == 0.0) s.position[2] = 0.0;  // -0.0 -> 0.0: the identity stays exact
  return s;
}

robot::Stance putt_stance(const System& system, std::array<double, 2> ball,
                          std::array<double, 2> hole, std::optional<double> aim) {
  check_ball_position(system.field(), ball, "ball");
  if (aim && !std::isfinite(*aim))
    throw InputError(fmt::format("aim: expected a number, got {}", *aim));
  return stance_for(system, ball, aim ? *aim : std::atan2(hole[1] - ball[1], hole[0] - ball[0]));
}

bool hit_reachable(const System& system, double angle, double speed) {
  const auto& c = system.config();
  return std::isfinite(angle) && std::isfinite(speed) && speed >= c.speed_min &&
         speed <= std::min(c.speed_max, system.module().club_speed_cap());
}

HitPose hit_pose(const System& system, std::array<double, 2> ball, double angle, double speed) {
  const auto& c = system.config();
  const field::Field& f = system.field();
  const bool fixed_reach = angle >= c.angle_min && angle <= c.angle_max &&
                           speed <= system.module().club_speed_cap(angle);
  HitPose pose;
  if (fixed_reach || !hit_reachable(system, angle, speed)) {
    // Out of every stance's reach too: aim 0, and the module refuses the request as before.
    if (ball != f.tee) pose.stance = stance_for(system, ball, 0.0);
    pose.angle = angle;
    return pose;
  }
  pose.stance = stance_for(system, ball, angle);
  pose.angle = 0.0;
  pose.turned = true;
  return pose;
}

SystemData::SystemData(const System& system)
    : arm(system.arm_world().make_data()),
      ball(system.ball_world().make_data()),
      scratch(std::make_unique<control::PuttScratch>()),
      perception(system.perception_factory() ? system.perception_factory()(system) : nullptr) {}

namespace {

/// A seed from a position's bits (the same situation, the same vision error).
std::uint64_t position_seed(std::uint64_t seed, std::array<double, 2> p) {
  std::uint64_t bits[2];
  std::memcpy(bits, p.data(), sizeof bits);
  return derive_seed(derive_seed(seed, bits[0]), bits[1]);
}

double gaussian(Rng& rng) {
  // Box-Muller from 53-bit uniforms (portable).
  const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
}

}  // namespace

std::array<double, 2> real_hole(const System& system, std::array<double, 2> hole) {
  return real_hole(system.plant(), hole);
}

void check_real_holes(const field::Field& field, const plant::Plant& plant,
                      const std::vector<std::array<double, 2>>& holes, std::string_view where) {
  if (plant.empty()) return;
  for (const auto& seen : holes) {
    const auto real = real_hole(plant, seen);
    try {
      field::check_hole_position(field, real);
    } catch (const InputError& e) {
      throw InputError(
          fmt::format("{}: plant {}: the hole seen at ({}, {}) is really at ({}, {}): {}", where,
                      plant.source.empty() ? "(in code)" : plant.source, seen[0], seen[1], real[0],
                      real[1], e.what()));
    }
  }
}

std::array<double, 2> real_hole(const plant::Plant& p, std::array<double, 2> hole) {
  const auto& offset = p.field.hole_offset;
  if (offset[0] != 0.0 || offset[1] != 0.0) hole = {hole[0] + offset[0], hole[1] + offset[1]};
  if (p.perception.noise > 0.0) {
    Rng rng(position_seed(21, hole));
    const double ex = gaussian(rng), ey = gaussian(rng);
    hole = {hole[0] - p.perception.noise * ex, hole[1] - p.perception.noise * ey};
  }
  return hole;
}

control::FullPuttResult arm_putt(const System& system, SystemData& data, std::array<double, 2> hole,
                                 double angle, double speed, control::FullPuttOptions options,
                                 control::PlantEffectValues effects) {
  field::check_hole_position(system.field(), hole);
  const plant::Plant& p = system.plant();
  if (!p.empty()) {
    const auto seen = hole;
    hole = real_hole(system, seen);
    field::check_hole_position(system.arm_world().field(), hole);
    if (p.arm.torque_noise > 0.0)
      effects.torque_noise = std::hypot(effects.torque_noise, p.arm.torque_noise);
    effects.launch_angle_bias += p.arm.launch_angle_bias;
    effects.club_speed_scale *= p.arm.club_speed_scale;
    effects.perception_latency += p.perception.latency;
    if (p.perception.noise > 0.0) {
      Rng rng(position_seed(22, seen));
      const double ex = gaussian(rng), ey = gaussian(rng);
      effects.perceived_ball_offset[0] += p.perception.noise * ex;
      effects.perceived_ball_offset[1] += p.perception.noise * ey;
    }
  }
  // The true world's effects as wrappers of what the harness simulates (validated here).
  control::PlantWrappers wrappers(system.module(), effects, options.seed);
  // The roll finishes in the ball-only world once the club has left the ball (same outcome,
  // notes/speed.md); the scratch caches the approach to the rest pose of recent angles.
  if (options.ball_world == nullptr) options.ball_world = &system.ball_world();
  if (options.perception_source == nullptr) options.perception_source = data.perception.get();
  // A field whose tee is not the robot frame's origin: the base stands beside the tee.
  if (options.stance.identity()) options.stance = stance_for(system, system.field().tee, 0.0);
  if (options.stance.identity())
    return control::full_system_putt(system.arm_world(), system.module(), data.arm.get(), hole,
                                     angle, speed, options, data.scratch.get(), wrappers.effects());
  check_ball_position(system.field(), {options.stance.position[0], options.stance.position[1]},
                      "ball");
  if (!data.stance_world || !(data.stance == options.stance)) {
    data.stance_arm.reset();
    data.stance_world = system.make_arm_world_at(options.stance);
    data.stance = options.stance;
    data.stance_arm = data.stance_world->make_data();
  }
  return control::full_system_putt(*data.stance_world, system.module(), data.stance_arm.get(), hole,
                                   angle, speed, options, data.scratch.get(), wrappers.effects());
}

control::FullPuttResult arm_hit(const System& system, SystemData& data,
                                const field::Situation& situation, double angle, double speed,
                                control::FullPuttOptions options,
                                const control::PlantEffectValues& effects) {
  const HitPose pose = hit_pose(system, situation.ball, angle, speed);
  options.stance = pose.stance;
  control::FullPuttResult r =
      arm_putt(system, data, situation.hole, pose.angle, speed, options, effects);
  if (pose.turned) {
    r.club.angle = std::remainder(r.club.angle + pose.stance.yaw, 2.0 * robot::kPi);
    r.launch.angle = std::remainder(r.launch.angle + pose.stance.yaw, 2.0 * robot::kPi);
  }
  return r;
}

sim::PuttOutcome ball_putt(const System& system, SystemData& data, std::array<double, 2> hole,
                           double angle, double speed, double record_interval,
                           std::optional<std::array<double, 2>> start) {
  field::check_hole_position(system.field(), hole);
  if (start) check_ball_position(system.field(), *start, "ball");
  if (!system.plant().empty()) {
    hole = real_hole(system, hole);
    field::check_hole_position(system.ball_world().field(), hole);
  }
  sim::PuttRequest request;
  request.angle = angle;
  request.speed = speed;
  request.record_interval = record_interval;
  request.start = start;
  return sim::simulate_putt(system.ball_world(), data.ball.get(), hole, request);
}

}  // namespace mg::system
