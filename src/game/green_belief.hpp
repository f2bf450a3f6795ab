#pragma once
/// What the robot believes of the green during a round, revised from every ball it watches
/// (docs/round.md, "Revising the belief"): the rolling resistance as a scale of each field's
/// survey and a tilt of the whole rig, the plant keys `rolling_resistance_scale` and
/// `extra_slope`. On each field the paths it saw there are fitted (belief::fit_green) under the
/// prior it had when it came to that field: the previous fields' result, so what it learned on
/// one lane carries over to the next.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "belief/path_fit.hpp"
#include "core/rng.hpp"
#include "field/field.hpp"
#include "plant/plant.hpp"
#include "sim/putt.hpp"

namespace mg::game {

/// Prior std of the belief before any ball is seen: the rolling resistance scale [-] and each
/// tilt [-] (the spread of `plant random`'s ranges, 0.8..1.2 and +-0.005).
inline constexpr double kPriorScaleStd = 0.12;
inline constexpr double kPriorSlopeStd = 0.003;

class GreenBelief {
 public:
  /// Starts from `initial`'s field keys (rolling_resistance_scale or an absolute
  /// rolling_resistance of `survey`, extra_slope); the robot sees ball positions with
  /// `vision_noise` [m] std per axis.
  GreenBelief(const plant::Plant& initial, const field::Field& survey, double vision_noise);

  /// The believed keys: rolling_resistance_scale and extra_slope (the identity before any
  /// revision from an identity start).
  const plant::Plant& plant() const { return belief_; }
  /// Std of the scale and the two tilts.
  const std::array<double, 3>& std() const { return std_; }
  /// Paths fitted in all (over every field).
  int paths() const { return paths_; }

  /// Adds a ball path the robot watched on `survey` (true centre positions, `hole` the cup as the
  /// robot sees it; its vision adds Gaussian error from `rng`) and revises. A path with nothing
  /// to fit (too short, at a wall at once) changes nothing. Returns true when the belief changed.
  bool watch(const field::Field& survey, std::array<double, 2> hole,
             const std::vector<sim::BallSample>& path, Rng& rng);

 private:
  struct FieldPaths {
    double prior_scale = 1.0;
    std::array<double, 2> prior_slope{};
    std::array<double, 3> prior_std{};
    std::vector<belief::ObservedPath> paths;
  };
  double noise_;
  plant::Plant belief_;
  std::array<double, 3> std_{};
  std::map<std::string, FieldPaths> fields_;
  int paths_ = 0;
};

}  // namespace mg::game
