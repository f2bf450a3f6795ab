#pragma once
/// The belief: the robot's estimate of the world and its uncertainty (docs/belief.md).
///
/// A plant (src/plant) is the world as it really is; a belief is what the robot thinks it is,
/// in the plant file's own terms, so that anything that can apply a plant can apply a belief.
/// Identification (path_fit.hpp, arm_fit.hpp, `minigolf identify`) estimates it from what the
/// robot measures, never from a plant file.
///
/// File: a plant file (YAML, `format_version: 1`, the same keys and validation, plant::
/// parse_plant) that may add, at the top level,
///   std:   the standard deviation of each estimated key, in the same shape as the plant's
///          `field` / `arm` / `perception` sections (a key absent or 0: not estimated);
///   putts: the number of putts the estimate rests on (a whole number >= 0).
/// Unknown or duplicate keys, non-finite and out-of-range values are one-line InputErrors that
/// name the file and the key.
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "field/field.hpp"
#include "plant/plant.hpp"

namespace mg::belief {

/// A plant whose every value is 0 (the `std` of nothing estimated; plant::Plant{} holds the
/// identity, which has club_speed_scale = club_restitution_scale = 1).
plant::Plant zero_plant();

struct Belief {
  plant::Plant estimate;            ///< the world as the robot believes it is (plant keys)
  plant::Plant std = zero_plant();  ///< std of each estimated key, same shape; 0: not estimated
  int putts = 0;                    ///< putts the estimate rests on
};

/// The largest `putts` a belief file may give.
inline constexpr int kMaxBeliefPutts = 1000000;

/// Parses belief YAML text; `source` names it in errors. Throws InputError.
Belief parse_belief(std::string_view yaml_text, const std::string& source);
/// Reads and parses a belief file (a regular file: a directory, FIFO or device is refused
/// before reading). Throws InputError/IoError naming the file.
Belief load_belief(const std::filesystem::path& path);

/// The belief as a file's text (parse_belief(belief_to_yaml(b)) == b up to `source`/`hash`):
/// the estimate as plant::plant_to_yaml writes it, then `std:` (non-zero keys only) and `putts`.
std::string belief_to_yaml(const Belief& belief);

/// The belief over `field` as the JSON:
///   {"field": {"rolling_resistance": rho (absolute: the field's times any scale),
///              "extra_slope": [sx, sy], "hole_offset": [dx, dy], "sliding_friction": mu},
///    "arm": {"launch_angle_bias": b, "club_speed_scale": s},
///    "std": {the same shape; 0: not estimated}, "putts": N}
nlohmann::json belief_to_json(const Belief& belief, const field::Field& field);

/// The lane as the robot believes it is: `surveyed` with the estimate's field keys applied
/// (plant::true_field with the estimate).
field::Field believed_field(const field::Field& surveyed, const Belief& belief);

/// Throws InputError (naming `source` and the key) unless every std value is finite and in
/// 0..the width of its key's range.
void validate_std(const plant::Plant& std, const std::string& source);

}  // namespace mg::belief
