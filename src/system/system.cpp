#include "system/system.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"
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
      throw InputError(fmt::format("--config: '{}' is a directory, expected a YAML file", config_path));
    config = control::load_module_config(config_path);
  }
  if (!field.empty()) config.field = field;
  if (!hitting_model.empty()) config.hitting_model = hitting_model;
  config.hitting_model = resolve_data_path(config.hitting_model).string();
  config.validate();
  return config;
}

System::System(const control::ModuleConfig& config) : System(config, field::load_field(config.field)) {}

System::System(const control::ModuleConfig& config, field::Field field) : config_(config) {
  config_.validate();
  config_.hitting_model = resolve_data_path(config_.hitting_model).string();
  ds::HittingModel hitting = ds::read_hitting_model(config_.hitting_model);
  arm_world_ = std::make_unique<sim::World>(control::make_world_with_arm(std::move(field)));
  ball_world_ = std::make_unique<sim::World>(control::make_ball_world(*arm_world_));
  module_ = std::make_unique<control::ModuleModel>(
      control::make_module_model(*arm_world_, std::move(hitting), config_));
}

void System::check_request(double angle, double speed, const std::string& what) const {
  const auto& c = config_;
  if (!std::isfinite(angle) || angle < c.angle_min || angle > c.angle_max)
    throw InputError(fmt::format("{}: angle: expected {}..{} rad (safe envelope), got {}", what,
                                 c.angle_min, c.angle_max, angle));
  if (!std::isfinite(speed) || speed < c.speed_min || speed > c.speed_max)
    throw InputError(fmt::format("{}: speed: expected {}..{} m/s (club speed, safe envelope), got {}",
                                 what, c.speed_min, c.speed_max, speed));
}

SystemData::SystemData(const System& system)
    : arm(system.arm_world().make_data()), ball(system.ball_world().make_data()),
      scratch(std::make_unique<control::PuttScratch>()) {}

control::FullPuttResult arm_putt(const System& system, SystemData& data, std::array<double, 2> hole,
                                 double angle, double speed, control::FullPuttOptions options) {
  field::check_hole_position(system.field(), hole);
  // The roll finishes in the ball-only world once the club has left the ball (same outcome,
  // notes/speed.md); the scratch caches the approach to the rest pose of recent angles.
  if (options.ball_world == nullptr) options.ball_world = &system.ball_world();
  return control::full_system_putt(system.arm_world(), system.module(), data.arm.get(), hole, angle,
                                   speed, options, data.scratch.get());
}

sim::PuttOutcome ball_putt(const System& system, SystemData& data, std::array<double, 2> hole,
                           double angle, double speed, double record_interval) {
  field::check_hole_position(system.field(), hole);
  sim::PuttRequest request;
  request.angle = angle;
  request.speed = speed;
  request.record_interval = record_interval;
  return sim::simulate_putt(system.ball_world(), data.ball.get(), hole, request);
}

}  // namespace mg::system
