#pragma once
/// One place that turns a configuration into a ready minigolf system (ARCHITECTURE.md "system"):
/// the field, the field's world with the WAM and club, the same field's ball-only world, the
/// hitting model and the module model. A `System` is immutable after construction and shared by
/// every thread; each thread owns a `SystemData` (its `mjData`s and scratch). Commands and
/// experiments build a System instead of assembling the world themselves.
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "control/full_system.hpp"
#include "control/module_config.hpp"
#include "field/field.hpp"
#include "sim/putt.hpp"
#include "sim/world.hpp"

namespace mg::system {

/// A relative path that does not exist from the working directory is tried from the repository
/// root (the parent of the data folder), so shipped defaults such as
/// `data/models/hitting-default.json` work from anywhere.
std::filesystem::path resolve_data_path(const std::string& text);

/// The module configuration of a run: the YAML file `config_path` (empty: defaults), then the
/// command line's overrides (`field`, `hitting_model`; empty: keep). The hitting-model path is
/// resolved here, once, for every command. Validated; throws InputError/IoError.
control::ModuleConfig load_config(const std::string& config_path, const std::string& field = "",
                                  const std::string& hitting_model = "");

class System {
 public:
  /// Loads the field (config.field) and the hitting model, builds both worlds and the module.
  /// Throws InputError/IoError for a bad configuration or file.
  explicit System(const control::ModuleConfig& config);
  /// The same with an already loaded field (config.field is then only a label).
  System(const control::ModuleConfig& config, field::Field field);
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  const control::ModuleConfig& config() const { return config_; }
  const field::Field& field() const { return arm_world_->field(); }
  const sim::World& arm_world() const { return *arm_world_; }    ///< field + WAM + club
  const sim::World& ball_world() const { return *ball_world_; }  ///< field only (the arm world's options)
  const control::ModuleModel& module() const { return *module_; }

  /// Throws InputError naming `what` unless (angle, speed) is inside the module's safe envelope.
  void check_request(double angle, double speed, const std::string& what) const;

 private:
  control::ModuleConfig config_;
  std::unique_ptr<sim::World> arm_world_;
  std::unique_ptr<sim::World> ball_world_;
  std::unique_ptr<control::ModuleModel> module_;
};

/// Per-thread mutable state for putts on one System.
struct SystemData {
  explicit SystemData(const System& system);
  sim::DataPtr arm;   ///< for full-system putts
  sim::DataPtr ball;  ///< for ball-only putts
  std::unique_ptr<control::PuttScratch> scratch;  ///< hand-off data, approach cache (bit-neutral)
};

/// The arm hits the ball (lockstep simulator mode) with the hole at `hole`: hitting angle
/// `angle` [rad], club speed `speed` [m/s]. Deterministic. Throws InputError for a bad hole.
control::FullPuttResult arm_putt(const System& system, SystemData& data, std::array<double, 2> hole,
                                 double angle, double speed, control::FullPuttOptions options = {});

/// The ball alone, launched from the tee at `angle` [rad], `speed` [m/s] (no spin).
sim::PuttOutcome ball_putt(const System& system, SystemData& data, std::array<double, 2> hole,
                           double angle, double speed, double record_interval = 0.0);

}  // namespace mg::system
