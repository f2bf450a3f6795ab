#include "game/green_belief.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.hpp"

namespace mg::game {
namespace {

constexpr double kMinScale = 0.5, kMaxScale = 2.0;  // rolling resistance x the survey's
constexpr double kMaxTilt = 0.05;                   // [-] dz/dx, dz/dy

}  // namespace

GreenBelief::GreenBelief(const plant::Plant& initial, const field::Field& survey,
                         double vision_noise)
    : noise_(vision_noise) {
  const double scale = plant::true_rolling_resistance(survey, initial) / survey.rolling_resistance;
  if (scale != 1.0) belief_.field.rolling_resistance_scale = scale;
  belief_.field.extra_slope = initial.field.extra_slope;
  std_ = {kPriorScaleStd, kPriorSlopeStd, kPriorSlopeStd};
}

bool GreenBelief::watch(const field::Field& survey, std::array<double, 2> hole,
                        const std::vector<sim::BallSample>& path, Rng& rng) {
  if (path.size() < 3) return false;
  auto it = fields_.find(survey.name);
  if (it == fields_.end()) {
    // A new lane: what the robot believes now is its prior there.
    FieldPaths f;
    f.prior_scale = belief_.field.rolling_resistance_scale.value_or(1.0);
    f.prior_slope = belief_.field.extra_slope;
    f.prior_std = std_;
    it = fields_.emplace(survey.name, std::move(f)).first;
  }
  FieldPaths& f = it->second;
  std::normal_distribution<double> normal(0.0, 1.0);
  belief::ObservedPath seen;
  seen.hole = hole;
  const double t0 = path.front().t;
  for (const auto& s : path)
    seen.samples.push_back({s.t - t0, s.x + noise_ * normal(rng), s.y + noise_ * normal(rng)});
  if (belief::rolling_span(survey, seen)[1] < belief::rolling_span(survey, seen)[0] + 3)
    return false;  // nothing on the open lane to fit
  f.paths.push_back(std::move(seen));
  const double rho = survey.rolling_resistance;
  belief::GreenPrior prior;
  prior.rolling_resistance = rho * f.prior_scale;
  prior.extra_slope = f.prior_slope;
  prior.std = {rho * f.prior_std[0], f.prior_std[1], f.prior_std[2]};
  belief::GreenEstimate e;
  try {
    e = belief::fit_green(survey, f.paths, prior, noise_);
  } catch (const NumericalError&) {
    f.paths.pop_back();
    return false;
  }
  const double scale = e.rolling_resistance / rho;
  if (!std::isfinite(scale) || !std::isfinite(e.extra_slope[0]) ||
      !std::isfinite(e.extra_slope[1])) {
    f.paths.pop_back();
    return false;
  }
  ++paths_;
  // Within what a green can be (and a plant file may say): a wild fit never breaks the round.
  belief_.field.rolling_resistance_scale = std::clamp(scale, kMinScale, kMaxScale);
  belief_.field.extra_slope = {std::clamp(e.extra_slope[0], -kMaxTilt, kMaxTilt),
                               std::clamp(e.extra_slope[1], -kMaxTilt, kMaxTilt)};
  std_ = {e.std[0] / rho, e.std[1], e.std[2]};
  return true;
}

}  // namespace mg::game
