#include "control/module_config.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/io.hpp"

namespace mg::control {

ModuleMode parse_module_mode(const std::string& name) {
  if (name == "simulator") return ModuleMode::kSimulator;
  if (name == "normal") return ModuleMode::kNormal;
  throw InputError(fmt::format("module config: mode: expected simulator|normal, got '{}'", name));
}

std::string to_string(ModuleMode mode) {
  return mode == ModuleMode::kSimulator ? "simulator" : "normal";
}

namespace {

void require(bool ok, const char* field, const std::string& expected, double got) {
  if (!ok)
    throw InputError(fmt::format("module config: {}: expected {}, got {}", field, expected, got));
}

void require_finite_positive(double v, const char* field) {
  require(std::isfinite(v) && v > 0.0, field, "a finite value > 0", v);
}

}  // namespace

void ModuleConfig::validate() const {
  if (field.empty()) throw InputError("module config: field: expected a name or path, got ''");
  if (hitting_model.empty())
    throw InputError("module config: hitting_model: expected a path, got ''");
  require(std::isfinite(core_rate) && core_rate >= 50.0 && core_rate <= 1000.0, "core_rate",
          "50..1000 Hz", core_rate);
  // Physics steps are 1 ms: the core period must be a whole number of steps.
  const double steps = 1000.0 / core_rate;
  require(std::abs(steps - std::round(steps)) < 1e-9, "core_rate", "1000/n Hz (whole 1 ms steps)",
          core_rate);
  require(robot_update_divider >= 1 && robot_update_divider <= 100, "robot_update_divider",
          "1..100", robot_update_divider);
  for (int j = 0; j < 7; ++j) {
    const auto i = static_cast<std::size_t>(j);
    require(std::isfinite(kp[i]) && kp[i] > 0.0, "kp", "finite > 0 per joint", kp[i]);
    require(std::isfinite(ki[i]) && ki[i] >= 0.0, "ki", "finite >= 0 per joint", ki[i]);
    require(std::isfinite(kd[i]) && kd[i] >= 0.0, "kd", "finite >= 0 per joint", kd[i]);
  }
  require(std::isfinite(integral_limit) && integral_limit >= 0.0, "integral_limit", ">= 0",
          integral_limit);
  require(fir_length >= 1 && fir_length <= 32, "fir_length", "1..32 taps", fir_length);
  require(std::isfinite(angle_min) && angle_min >= -1.0 && angle_min < 0.0, "angle_min",
          "-1.0 <= angle_min < 0 rad", angle_min);
  require(std::isfinite(angle_max) && angle_max > 0.0 && angle_max <= 1.0, "angle_max",
          "0 < angle_max <= 1.0 rad", angle_max);
  require(std::isfinite(speed_min) && speed_min > 0.0, "speed_min", "> 0 m/s", speed_min);
  require(std::isfinite(speed_max) && speed_max > speed_min && speed_max <= 3.0, "speed_max",
          "speed_min < speed_max <= 3.0 m/s (WAM maximum)", speed_max);
  require(std::isfinite(arm_speed_cap) && arm_speed_cap >= speed_min && arm_speed_cap <= 3.0,
          "arm_speed_cap", "speed_min..3.0 m/s", arm_speed_cap);
  require(std::isfinite(arm_speed_cap_negative) && arm_speed_cap_negative >= speed_min &&
              arm_speed_cap_negative <= arm_speed_cap,
          "arm_speed_cap_negative", "speed_min..arm_speed_cap m/s", arm_speed_cap_negative);
  require(
      std::isfinite(negative_cap_angle) && negative_cap_angle > 0.0 && negative_cap_angle <= 1.0,
      "negative_cap_angle", "0..1 rad", negative_cap_angle);
  for (double v : rest_offset) require(std::isfinite(v), "rest_offset", "finite", v);
  require(rest_offset[0] < -0.05, "rest_offset", "x < -0.05 m (behind the ball)", rest_offset[0]);
  require(std::isfinite(club_face_offset) && club_face_offset >= 0.0 && club_face_offset < 0.1,
          "club_face_offset", "0..0.1 m", club_face_offset);
  require_finite_positive(rest_speed, "rest_speed");
  require_finite_positive(rest_turn_rate, "rest_turn_rate");
  require_finite_positive(rest_tolerance, "rest_tolerance");
  require_finite_positive(rest_heading_tolerance, "rest_heading_tolerance");
  require(std::isfinite(brake_lift_height) && brake_lift_height >= 0.0 && brake_lift_height <= 0.2,
          "brake_lift_height", "0..0.2 m", brake_lift_height);
  require_finite_positive(brake_time, "brake_time");
  require_finite_positive(stationary_threshold, "stationary_threshold");
  require_finite_positive(ball_moving_speed, "ball_moving_speed");
  require_finite_positive(passed_distance, "passed_distance");
  require_finite_positive(ball_moved_distance, "ball_moved_distance");
  require_finite_positive(max_hit_duration, "max_hit_duration");
  require_finite_positive(reference_leash, "reference_leash");
  require(std::isfinite(hit_ramp_time) && hit_ramp_time > 0.0 && hit_ramp_time <= 1.0,
          "hit_ramp_time", "0..1 s", hit_ramp_time);
  require(std::isfinite(velocity_fault_factor) && velocity_fault_factor >= 1.0,
          "velocity_fault_factor", ">= 1", velocity_fault_factor);
  require(std::isfinite(perception_max_age) && perception_max_age >= core_period() &&
              perception_max_age <= 5.0,
          "perception_max_age", "one core period..5 s", perception_max_age);
  require(std::isfinite(ball_tolerance) && ball_tolerance > 0.0 && ball_tolerance <= 0.2,
          "ball_tolerance", "0..0.2 m", ball_tolerance);
  require(overrun_streak_limit >= 1 && overrun_streak_limit <= 10000, "overrun_streak_limit",
          "1..10000 ticks", overrun_streak_limit);
  require(vision_port >= 0 && vision_port <= 65535, "vision_port", "0..65535 (0: any free port)",
          vision_port);
  require(std::isfinite(vision_sim_rate) && vision_sim_rate >= 1.0 && vision_sim_rate <= 1000.0,
          "vision_sim_rate", "1..1000 Hz", vision_sim_rate);
  require(std::isfinite(vision_sim_noise) && vision_sim_noise >= 0.0 && vision_sim_noise <= 0.5,
          "vision_sim_noise", "0..0.5 m", vision_sim_noise);
  require(
      std::isfinite(vision_sim_latency) && vision_sim_latency >= 0.0 && vision_sim_latency <= 5.0,
      "vision_sim_latency", "0..5 s", vision_sim_latency);
  require(
      std::isfinite(vision_sim_dropout) && vision_sim_dropout >= 0.0 && vision_sim_dropout <= 1.0,
      "vision_sim_dropout", "0..1", vision_sim_dropout);
}

namespace {

std::array<double, 7> read_gains(const YAML::Node& n, const char* field) {
  std::array<double, 7> g{};
  if (n.IsScalar()) {
    g.fill(n.as<double>());
  } else if (n.IsSequence() && n.size() == 7) {
    for (std::size_t i = 0; i < 7; ++i) g[i] = n[i].as<double>();
  } else {
    throw InputError(fmt::format("module config: {}: expected a number or a list of 7", field));
  }
  return g;
}

}  // namespace

ModuleConfig parse_module_config(const std::string& yaml_text, const std::string& source) {
  ModuleConfig c;
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: not valid YAML: {}", source, e.what()));
  }
  if (root.IsNull()) return c;
  if (!root.IsMap()) throw InputError(fmt::format("{}: expected a YAML mapping", source));
  static const std::set<std::string> known{"field",
                                           "hitting_model",
                                           "mode",
                                           "core_rate",
                                           "robot_update_divider",
                                           "kp",
                                           "ki",
                                           "kd",
                                           "integral_limit",
                                           "fir_length",
                                           "angle_min",
                                           "angle_max",
                                           "speed_min",
                                           "speed_max",
                                           "arm_speed_cap",
                                           "arm_speed_cap_negative",
                                           "negative_cap_angle",
                                           "rest_offset",
                                           "club_face_offset",
                                           "rest_speed",
                                           "rest_turn_rate",
                                           "rest_tolerance",
                                           "rest_heading_tolerance",
                                           "brake_lift_height",
                                           "brake_time",
                                           "stationary_threshold",
                                           "ball_moving_speed",
                                           "passed_distance",
                                           "ball_moved_distance",
                                           "max_hit_duration",
                                           "hit_ramp_time",
                                           "reference_leash",
                                           "velocity_fault_factor",
                                           "params_model",
                                           "record",
                                           "perception_max_age",
                                           "ball_tolerance",
                                           "overrun_streak_limit",
                                           "vision_address",
                                           "vision_port",
                                           "vision_sim_rate",
                                           "vision_sim_noise",
                                           "vision_sim_latency",
                                           "vision_sim_dropout"};
  std::string key;
  try {
    for (const auto& kv : root) {
      key = kv.first.as<std::string>();
      if (!known.count(key)) throw InputError(fmt::format("{}: unknown key '{}'", source, key));
      const YAML::Node& v = kv.second;
      auto num = [&](double& out) { out = v.as<double>(); };
      if (key == "field")
        c.field = v.as<std::string>();
      else if (key == "hitting_model")
        c.hitting_model = v.as<std::string>();
      else if (key == "mode")
        c.mode = parse_module_mode(v.as<std::string>());
      else if (key == "core_rate")
        num(c.core_rate);
      else if (key == "robot_update_divider")
        c.robot_update_divider = v.as<int>();
      else if (key == "kp")
        c.kp = read_gains(v, "kp");
      else if (key == "ki")
        c.ki = read_gains(v, "ki");
      else if (key == "kd")
        c.kd = read_gains(v, "kd");
      else if (key == "integral_limit")
        num(c.integral_limit);
      else if (key == "fir_length")
        c.fir_length = v.as<int>();
      else if (key == "angle_min")
        num(c.angle_min);
      else if (key == "angle_max")
        num(c.angle_max);
      else if (key == "speed_min")
        num(c.speed_min);
      else if (key == "speed_max")
        num(c.speed_max);
      else if (key == "arm_speed_cap")
        num(c.arm_speed_cap);
      else if (key == "arm_speed_cap_negative")
        num(c.arm_speed_cap_negative);
      else if (key == "negative_cap_angle")
        num(c.negative_cap_angle);
      else if (key == "rest_offset") {
        if (!v.IsSequence() || v.size() != 3)
          throw InputError(fmt::format("{}: rest_offset: expected a list of 3", source));
        for (std::size_t i = 0; i < 3; ++i) c.rest_offset[i] = v[i].as<double>();
      } else if (key == "club_face_offset")
        num(c.club_face_offset);
      else if (key == "rest_speed")
        num(c.rest_speed);
      else if (key == "rest_turn_rate")
        num(c.rest_turn_rate);
      else if (key == "rest_tolerance")
        num(c.rest_tolerance);
      else if (key == "rest_heading_tolerance")
        num(c.rest_heading_tolerance);
      else if (key == "brake_lift_height")
        num(c.brake_lift_height);
      else if (key == "brake_time")
        num(c.brake_time);
      else if (key == "stationary_threshold")
        num(c.stationary_threshold);
      else if (key == "ball_moving_speed")
        num(c.ball_moving_speed);
      else if (key == "passed_distance")
        num(c.passed_distance);
      else if (key == "ball_moved_distance")
        num(c.ball_moved_distance);
      else if (key == "max_hit_duration")
        num(c.max_hit_duration);
      else if (key == "hit_ramp_time")
        num(c.hit_ramp_time);
      else if (key == "reference_leash")
        num(c.reference_leash);
      else if (key == "velocity_fault_factor")
        num(c.velocity_fault_factor);
      else if (key == "params_model")
        c.params_model = v.as<std::string>();
      else if (key == "record")
        c.record = v.as<std::string>();
      else if (key == "perception_max_age")
        num(c.perception_max_age);
      else if (key == "ball_tolerance")
        num(c.ball_tolerance);
      else if (key == "overrun_streak_limit")
        c.overrun_streak_limit = v.as<int>();
      else if (key == "vision_address")
        c.vision_address = v.as<std::string>();
      else if (key == "vision_port")
        c.vision_port = v.as<int>();
      else if (key == "vision_sim_rate")
        num(c.vision_sim_rate);
      else if (key == "vision_sim_noise")
        num(c.vision_sim_noise);
      else if (key == "vision_sim_latency")
        num(c.vision_sim_latency);
      else if (key == "vision_sim_dropout")
        num(c.vision_sim_dropout);
    }
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: {}: wrong type: {}", source, key, e.what()));
  }
  c.validate();
  return c;
}

ModuleConfig load_module_config(const std::filesystem::path& path) {
  return parse_module_config(read_text_file(path), path.string());
}

}  // namespace mg::control
