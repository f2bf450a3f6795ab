#pragma once
/// The plant: how the world really is, where it differs from what the robot believes
/// (docs/reality.md, docs/architecture.md).
///
/// The robot's knowledge is its field file, arm and hitting models and learned models. A plant
/// file says how the simulated world that putts happen in differs: grass, a tilt the survey
/// missed, where the hole really is, the club face, arm friction, vision noise and latency. Only
/// the world builder (system::System) and the oracle read a plant; an empty plant is the
/// identity (the same bits as no plant).
///
/// File (YAML, `format_version: 1` required, every other key optional, unknown keys and keys
/// given twice are an error; an empty file is an error, not the identity):
///   field:      rolling_resistance | rolling_resistance_scale, sliding_friction |
///               sliding_friction_scale, extra_slope [dz/dx, dz/dy], hole_offset [m, m],
///               bumps (a list of {center: [x, y], height, sigma: [sx, sy]} [m]: Gaussian
///               bumps and dips of the real green that the survey missed)
///   arm:        launch_angle_bias [rad], club_speed_scale, club_restitution_scale,
///               joint_friction [7 x N m], torque_noise [fraction of the torque limits]
///   perception: noise [m, std per axis], latency [s]
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "field/field.hpp"

namespace mg::plant {

inline constexpr int kPlantFormatVersion = 1;

/// Physical truth of the lane.
struct FieldTruth {
  std::optional<double> rolling_resistance;        ///< Penner rho [-], replaces the field's
  std::optional<double> rolling_resistance_scale;  ///< or: the field's rho times this
  std::optional<double> sliding_friction;          ///< [-], replaces the field's
  std::optional<double> sliding_friction_scale;    ///< or: the field's times this
  std::array<double, 2> extra_slope{0.0, 0.0};     ///< dz/dx, dz/dy added to the whole surface
  std::array<double, 2> hole_offset{0.0, 0.0};     ///< [m] real hole - where the robot sees it
  /// Unsurveyed bumps (negative height: dips) added to the surface. No belief key estimates
  /// them: a world with bumps is one the robot's model cannot express (docs/belief.md, "Beyond
  /// the plant's keys").
  std::vector<field::BumpTerm> bumps;
};

/// At most this many bumps in a plant.
inline constexpr std::size_t kMaxPlantBumps = 32;

/// Physical truth of the arm and club.
struct ArmTruth {
  double launch_angle_bias = 0.0;          ///< [rad] added to the ball's launch direction
  double club_speed_scale = 1.0;           ///< the arm reaches this fraction of the commanded speed
  double club_restitution_scale = 1.0;     ///< the club face's restitution times this
  std::array<double, 7> joint_friction{};  ///< [N m] Coulomb friction per joint
  double torque_noise = 0.0;               ///< joint-torque noise std, fraction of the limits
};

/// Physical truth of the vision.
struct PerceptionTruth {
  double noise = 0.0;    ///< [m] std per axis of the perceived ball and hole (per putt)
  double latency = 0.0;  ///< [s] age of what the module perceives
};

struct Plant {
  FieldTruth field;
  ArmTruth arm;
  PerceptionTruth perception;
  std::string source;  ///< the file it came from ("" for one made in code)
  std::string hash;    ///< FNV-1a 64 of the file's bytes, 16 hex digits ("" when not from a file)

  /// True when every value is the identity: the world is the robot's model.
  bool empty() const;
  bool field_changed() const;  ///< a lane property differs (the worlds must be rebuilt)
  bool arm_changed() const;    ///< friction or restitution differs (the arm world differs)
  /// Throws InputError naming the key of the first out-of-range value.
  void validate() const;
};

/// Parses plant YAML text; `source` names it in errors. Throws InputError.
Plant parse_plant(std::string_view yaml_text, const std::string& source);
/// The bytes of a plant file (a regular file of at most 1 MiB). Throws InputError/IoError.
std::string read_plant_file(const std::filesystem::path& path);
/// Reads and parses a plant file (source and hash set). Throws InputError/IoError.
Plant load_plant(const std::filesystem::path& path);

/// The lane as it really is: `belief` with the plant's field truths applied (grass, tilt); the
/// hole offset is applied per putt (system::arm_putt). Without field changes the same value.
field::Field true_field(const field::Field& belief, const Plant& plant);

/// The effective rolling resistance and sliding friction of `plant` over a field.
double true_rolling_resistance(const field::Field& belief, const Plant& plant);
double true_sliding_friction(const field::Field& belief, const Plant& plant);

/// A plant drawn from the documented realistic ranges (docs/reality.md), as scales and offsets
/// that fit any field. Deterministic for a seed (portable: no std distributions).
Plant random_plant(std::uint64_t seed);

/// The plant as a YAML file's text (format_version 1; only keys that differ from the identity).
std::string plant_to_yaml(const Plant& plant);

/// FNV-1a 64 of `bytes` as 16 hex digits.
std::string content_hash(std::string_view bytes);

}  // namespace mg::plant
