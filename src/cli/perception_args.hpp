#pragma once
/// `--perception truth|camera [--rig R] [--calibration C]`: what the module sees, one parser for
/// every putting command (putt, evaluate, self-teach, play, identify; docs/perception.md).
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "field/field.hpp"
#include "system/system.hpp"
#include "vision/camera_perception.hpp"

namespace mg::cli {

struct PerceptionArgs {
  std::string perception = "truth";
  std::string rig = vision::kDefaultRig;
  std::string calibration;
  CLI::Option* rig_option = nullptr;
  CLI::Option* calibration_option = nullptr;
};

/// Adds --perception, --rig and --calibration to `cmd`.
void add_perception_options(CLI::App* cmd, PerceptionArgs& a);

/// The cameras of `a` (nullopt: the truth), loaded and checked before any work: the rig, the
/// calibration against it, and that the rig sees every one of `fields` (the worlds as they are).
/// InputError (one line naming the option or the file, exit 2): --rig or --calibration without
/// --perception camera, a bad or missing file, a rig that does not see a lane.
std::optional<vision::Cameras> load_perception(const PerceptionArgs& a,
                                               const std::vector<const field::Field*>& fields);

/// The System's perception of `a` (empty: the truth), checked as load_perception.
system::PerceptionFactory perception_factory(const PerceptionArgs& a,
                                             const std::vector<const field::Field*>& fields);

}  // namespace mg::cli
