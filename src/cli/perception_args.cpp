#include "cli/perception_args.hpp"

#include "core/error.hpp"

namespace mg::cli {

void add_perception_options(CLI::App* cmd, PerceptionArgs& a) {
  cmd->add_option("--perception", a.perception,
                  "What the module sees: truth (the simulator's) or camera (the rig's cameras "
                  "render the simulation; needs a display or xvfb-run)")
      ->check(CLI::IsMember({"truth", "camera"}))
      ->capture_default_str();
  a.rig_option =
      cmd->add_option("--rig", a.rig, "With --perception camera: rig file or shipped rig name")
          ->capture_default_str();
  a.calibration_option = cmd->add_option(
      "--calibration", a.calibration,
      "With --perception camera: calibration file (vision calibrate; default: the rig's exact "
      "cameras)");
}

std::optional<vision::Cameras> load_perception(const PerceptionArgs& a,
                                               const std::vector<const field::Field*>& fields) {
  if (a.perception != "camera") {
    if (a.rig_option && a.rig_option->count() > 0)
      throw InputError("--rig: only with --perception camera");
    if (a.calibration_option && a.calibration_option->count() > 0)
      throw InputError("--calibration: only with --perception camera");
    return std::nullopt;
  }
  vision::Cameras cameras = vision::load_cameras(a.rig, a.calibration);
  for (const field::Field* f : fields) vision::check_rig_sees_field(cameras.rig, *f);
  return cameras;
}

system::PerceptionFactory perception_factory(const PerceptionArgs& a,
                                             const std::vector<const field::Field*>& fields) {
  std::optional<vision::Cameras> cameras = load_perception(a, fields);
  if (!cameras) return {};
  return vision::camera_perception(std::move(*cameras));
}

}  // namespace mg::cli
