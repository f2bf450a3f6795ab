#include "control/module_config.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "field/map_reader.hpp"

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

void ControllerConfig::validate() const {
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
}

void SessionConfig::validate() const {
  if (field.empty()) throw InputError("module config: field: expected a name or path, got ''");
  if (hitting_model.empty())
    throw InputError("module config: hitting_model: expected a path, got ''");
  require(overrun_streak_limit >= 1 && overrun_streak_limit <= 10000, "overrun_streak_limit",
          "1..10000 ticks", overrun_streak_limit);
}

void VisionConfig::validate() const {
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

void ModuleConfig::validate() const {
  ControllerConfig::validate();
  SessionConfig::validate();
  VisionConfig::validate();
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

/// One key of the file: the part it belongs to and how it is read.
struct Key {
  const char* part;  ///< "controller" | "session" | "vision"
  void (*read)(ModuleConfig&, const YAML::Node&);
};

#define MG_NUMBER(name)                                                                   \
  {                                                                                       \
#name, {                                                                              \
      "controller", [](ModuleConfig& c, const YAML::Node& v) { c.name = v.as<double>(); } \
    }                                                                                     \
  }

const std::map<std::string, Key>& keys() {
  static const std::map<std::string, Key> table{
      {"mode",
       {"controller",
        [](ModuleConfig& c, const YAML::Node& v) {
          c.mode = parse_module_mode(v.as<std::string>());
        }}},
      MG_NUMBER(core_rate),
      {"robot_update_divider",
       {"controller",
        [](ModuleConfig& c, const YAML::Node& v) { c.robot_update_divider = v.as<int>(); }}},
      {"kp",
       {"controller", [](ModuleConfig& c, const YAML::Node& v) { c.kp = read_gains(v, "kp"); }}},
      {"ki",
       {"controller", [](ModuleConfig& c, const YAML::Node& v) { c.ki = read_gains(v, "ki"); }}},
      {"kd",
       {"controller", [](ModuleConfig& c, const YAML::Node& v) { c.kd = read_gains(v, "kd"); }}},
      MG_NUMBER(integral_limit),
      {"fir_length",
       {"controller", [](ModuleConfig& c, const YAML::Node& v) { c.fir_length = v.as<int>(); }}},
      MG_NUMBER(angle_min),
      MG_NUMBER(angle_max),
      MG_NUMBER(speed_min),
      MG_NUMBER(speed_max),
      MG_NUMBER(arm_speed_cap),
      MG_NUMBER(arm_speed_cap_negative),
      MG_NUMBER(negative_cap_angle),
      {"rest_offset",
       {"controller",
        [](ModuleConfig& c, const YAML::Node& v) {
          if (!v.IsSequence() || v.size() != 3)
            throw InputError("rest_offset: expected a list of 3");
          for (std::size_t i = 0; i < 3; ++i) c.rest_offset[i] = v[i].as<double>();
        }}},
      MG_NUMBER(club_face_offset),
      MG_NUMBER(rest_speed),
      MG_NUMBER(rest_turn_rate),
      MG_NUMBER(rest_tolerance),
      MG_NUMBER(rest_heading_tolerance),
      MG_NUMBER(brake_lift_height),
      MG_NUMBER(brake_time),
      MG_NUMBER(stationary_threshold),
      MG_NUMBER(ball_moving_speed),
      MG_NUMBER(passed_distance),
      MG_NUMBER(ball_moved_distance),
      MG_NUMBER(max_hit_duration),
      MG_NUMBER(hit_ramp_time),
      MG_NUMBER(reference_leash),
      MG_NUMBER(velocity_fault_factor),
      MG_NUMBER(perception_max_age),
      MG_NUMBER(ball_tolerance),
      {"field",
       {"session", [](ModuleConfig& c, const YAML::Node& v) { c.field = v.as<std::string>(); }}},
      {"hitting_model",
       {"session",
        [](ModuleConfig& c, const YAML::Node& v) { c.hitting_model = v.as<std::string>(); }}},
      {"params_model",
       {"session",
        [](ModuleConfig& c, const YAML::Node& v) { c.params_model = v.as<std::string>(); }}},
      {"record",
       {"session", [](ModuleConfig& c, const YAML::Node& v) { c.record = v.as<std::string>(); }}},
      {"overrun_streak_limit",
       {"session",
        [](ModuleConfig& c, const YAML::Node& v) { c.overrun_streak_limit = v.as<int>(); }}},
      {"vision_address",
       {"vision",
        [](ModuleConfig& c, const YAML::Node& v) { c.vision_address = v.as<std::string>(); }}},
      {"vision_port",
       {"vision", [](ModuleConfig& c, const YAML::Node& v) { c.vision_port = v.as<int>(); }}},
      {"vision_sim_rate",
       {"vision",
        [](ModuleConfig& c, const YAML::Node& v) { c.vision_sim_rate = v.as<double>(); }}},
      {"vision_sim_noise",
       {"vision",
        [](ModuleConfig& c, const YAML::Node& v) { c.vision_sim_noise = v.as<double>(); }}},
      {"vision_sim_latency",
       {"vision",
        [](ModuleConfig& c, const YAML::Node& v) { c.vision_sim_latency = v.as<double>(); }}},
      {"vision_sim_dropout",
       {"vision",
        [](ModuleConfig& c, const YAML::Node& v) { c.vision_sim_dropout = v.as<double>(); }}},
  };
  return table;
}

#undef MG_NUMBER

/// Reads the keys of one mapping: the file's top level (`part` empty: any key, or a group) or
/// one group (`part` names it: only its keys).
void read_keys(ModuleConfig& c, const YAML::Node& map, const std::string& part,
               const std::string& source) {
  std::string key;
  try {
    for (const auto& kv : map) {
      key = kv.first.as<std::string>();
      if (part.empty() && (key == "controller" || key == "session" || key == "vision")) {
        if (!kv.second.IsMap())
          throw InputError(fmt::format("{}: {}: expected a mapping of keys", source, key));
        read_keys(c, kv.second, key, source);
        continue;
      }
      const auto it = keys().find(key);
      if (it == keys().end()) throw InputError(fmt::format("{}: unknown key '{}'", source, key));
      if (!part.empty() && part != it->second.part)
        throw InputError(
            fmt::format("{}: {}: '{}' belongs under '{}'", source, part, key, it->second.part));
      try {
        it->second.read(c, kv.second);
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", source, e.what()));
      }
    }
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: {}: wrong type: {}", source, key, e.what()));
  }
}

}  // namespace

ModuleConfig parse_module_config(const std::string& yaml_text, const std::string& source) {
  ModuleConfig c;
  const YAML::Node root = field::load_yaml(yaml_text, source);
  if (!root || root.IsNull()) return c;
  if (!root.IsMap()) throw InputError(fmt::format("{}: expected a YAML mapping", source));
  read_keys(c, root, "", source);
  c.validate();
  return c;
}

ModuleConfig load_module_config(const std::filesystem::path& path) {
  return parse_module_config(read_text_file(path), path.string());
}

}  // namespace mg::control
