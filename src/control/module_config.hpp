#pragma once
/// Configuration of the minigolf module (thesis chapter 4): a plain struct with every default in
/// one place, loaded from YAML once and validated once (`validate()` throws mg::InputError naming
/// the field). Nothing here is touched by the 500 Hz core update except read-only.
#include <array>
#include <filesystem>
#include <string>

namespace mg::control {

/// Where ball/hole come from and which safety policy applies (docs/control.md).
enum class ModuleMode {
  kSimulator,  ///< world state from the simulation; full speed envelope
  kNormal,     ///< real-arm policy: end-point speed capped at robot::kSafeEndpointSpeed, slower IK
};
ModuleMode parse_module_mode(const std::string& name);  ///< "simulator" | "normal"; InputError
std::string to_string(ModuleMode mode);

/// What the 500 Hz controller (minigolf_module, mujoco_arm) reads: rates, gains, the hit
/// envelope, the DS's rest and brake motions, hit and fault detection. It names no file, address
/// or thread, so a controller built from it runs the same behind any session or plant.
struct ControllerConfig {
  ModuleMode mode = ModuleMode::kSimulator;

  double core_rate = 500.0;  ///< [Hz] core update rate (physics runs at 1 kHz: 2 steps per tick)
  int robot_update_divider = 5;  ///< robot update (DS evaluation) every this many core ticks

  /// Computed-torque PID gains per joint, in acceleration units (they are multiplied by M(q)
  /// through the RNEA): kp [1/s^2], ki [1/s^3], kd [1/s]. Critically damped kd = 2 sqrt(kp).
  /// ki = 0: the controller's model equals the plant here (no friction); kept for the real arm.
  std::array<double, 7> kp{400, 400, 400, 400, 400, 400, 400};
  std::array<double, 7> ki{0, 0, 0, 0, 0, 0, 0};
  std::array<double, 7> kd{40, 40, 40, 40, 40, 40, 40};
  double integral_limit = 0.05;  ///< [rad s] anti-windup clamp of the PID integral per joint

  /// Moving-average FIR low-pass on the desired joint velocities (thesis 4.2.2), taps at the core
  /// rate. 5 taps = 4 ms group delay, first zero at 100 Hz.
  int fir_length = 5;

  /// Safe envelope of a hit request (thesis 4.3): angle [rad] about +z from psi0, club speed [m/s].
  /// angle_min -0.3: hitting further away from the arm's side saturates J2 (raw torque demand
  /// 10x the limits, launch errors 0.02-0.06 rad, joints 1.2x their velocity limits; measured).
  double angle_min = -0.3, angle_max = 0.6;
  double speed_min = 0.3, speed_max = 3.0;
  /// [m/s] what the DS may ask of the club in simulator mode for hitting angles >= 0: above ~2.6
  /// m/s the launch speed stops growing (notes/control.md). Faster requests hit at the cap along
  /// the right direction instead of off-centre.
  double arm_speed_cap = 2.6;
  /// [m/s] the cap for angles <= -negative_cap_angle (linear in between): hitting away from the
  /// arm's side, J2 saturates above ~1.3-1.6 m/s and the path bends (launch errors > 0.01 rad).
  double arm_speed_cap_negative = 1.3;
  double negative_cap_angle = 0.15;  ///< [rad]

  /// Rest pose of the DS point p (the point one club-face offset ahead of the face centre) relative
  /// to x*, in the hitting frame R(theta): behind the ball and above it [m].
  std::array<double, 3> rest_offset{-0.30, 0.0, 0.06};
  /// [m] p = face centre + offset psi: at impact the face (a plane through the face centre) meets
  /// the ball's back when p reaches the ball centre x*, so the offset is the ball radius.
  double club_face_offset = 0.021335;
  double rest_speed = 0.25;              ///< [m/s] speed of the moving rest set-point
  double rest_turn_rate = 0.8;           ///< [rad/s] heading rate of the rest set-point
  double rest_tolerance = 0.003;         ///< [m] face within this of the rest pose counts as there
  double rest_heading_tolerance = 0.01;  ///< [rad]

  double brake_lift_height = 0.04;     ///< [m] club lifted this much while braking
  double brake_time = 0.15;            ///< [s] velocity target ramps to zero over this time
  double stationary_threshold = 0.05;  ///< [rad/s] every joint slower: stationary
  /// [m/s] the putt harness (full_system_putt) counts the simulated ball faster than this as hit
  /// (with the simulator's contact); the module itself detects the hit from measurements only.
  double ball_moving_speed = 0.05;
  /// [m] the module counts the ball as hit once the perceived ball has moved this far
  /// (horizontally) from where it was seen when the hit began: 10x the vision noise.
  double ball_moved_distance = 0.01;
  double passed_distance = 0.06;  ///< [m] DS point this far past x* without contact: passed
  /// [m] the integrated DS reference may lead the kinematic reference by at most this much.
  double reference_leash = 0.005;
  double hit_ramp_time = 0.2;     ///< [s] DS velocity ramped in (smoothstep) from the rest pose
  double max_hit_duration = 3.0;  ///< [s] a hit longer than this is a fault

  /// Faults: measured joint speed above this fraction of its limit, or a joint outside its range.
  double velocity_fault_factor = 1.5;

  /// [s] perception older than this is stale: no hit starts, a running hit brakes (lost ball).
  double perception_max_age = 0.2;
  /// [m] the perceived ball must lie this close (horizontally) to the hitting point to hit.
  double ball_tolerance = 0.03;

  /// Throws mg::InputError naming the first bad field ("expected X, got Y").
  void validate() const;
  /// [s] core period.
  double core_period() const { return 1.0 / core_rate; }
  /// Every field equal (what the approach cache keys on).
  bool operator==(const ControllerConfig&) const = default;
};

/// What a session (console, putt harness) needs around the controller: the world it loads, the
/// models it reads, where it records, and when the real-time loop gives up.
struct SessionConfig {
  std::string field = "flat";                                      ///< shipped field name or path
  std::string hitting_model = "data/models/hitting-default.json";  ///< hitting DS model file
  /// Parameter model (`minigolf train` JSON) for the console's `auto`; empty: none loaded.
  std::string params_model;
  /// CSV file the console records to from the start (`record on FILE` later); empty: off.
  std::string record;

  /// Real-time mode: this many core ticks in a row that miss their deadline are a fault.
  int overrun_streak_limit = 10;

  void validate() const;  ///< as ControllerConfig::validate
  bool operator==(const SessionConfig&) const = default;
};

/// The vision feed (normal mode) and the console's built-in vision simulator.
struct VisionConfig {
  /// Normal mode: UDP address and port the vision feed listens on (0: any free port, printed).
  /// 127.0.0.1 takes only this machine's senders; a vision system elsewhere needs 0.0.0.0.
  std::string vision_address = "127.0.0.1";
  int vision_port = 47001;
  /// The console's built-in vision simulator (`--vision-sim`): it observes the simulated world
  /// and publishes to vision_port over loopback, like `minigolf vision-sim`.
  double vision_sim_rate = 60.0;     ///< [Hz]
  double vision_sim_noise = 0.001;   ///< [m] Gaussian noise std per coordinate
  double vision_sim_latency = 0.02;  ///< [s] capture to send
  double vision_sim_dropout = 0.0;   ///< probability a message is not sent

  void validate() const;  ///< as ControllerConfig::validate
  bool operator==(const VisionConfig&) const = default;
};

/// The module's whole configuration, one YAML file: the three parts above. Each layer takes only
/// its part (the controller a `const ControllerConfig&`); the parts are bases, not members, so the
/// file's flat keys read the same in code (`config.kp`, `config.vision_port`).
struct ModuleConfig : ControllerConfig, SessionConfig, VisionConfig {
  void validate() const;  ///< every part
  bool operator==(const ModuleConfig&) const = default;
};

/// Reads a YAML file; missing keys keep their defaults, unknown keys are an error. Keys are flat
/// or grouped under `controller:`, `session:` and `vision:` (a key in the wrong group is an
/// error). Gains may be a scalar (all joints) or a list of 7. Throws InputError/IoError; the result
/// is validated.
ModuleConfig load_module_config(const std::filesystem::path& path);
/// The same from YAML text (`source` names it in messages).
ModuleConfig parse_module_config(const std::string& yaml_text, const std::string& source);

}  // namespace mg::control
