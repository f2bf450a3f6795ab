#pragma once
/// Identification of the green from observed ball paths (docs/belief.md).
///
/// The rolling ball is a point on the lane as the robot surveyed it plus an unknown tilt
/// (plant key `extra_slope`), slowed by Penner's rolling resistance rho (`rolling_resistance`).
/// `fit_green` fits rho and the tilt to the rolling part of observed paths by Gauss-Newton /
/// Levenberg-Marquardt, each path's state where its rolling part starts being a nuisance
/// parameter, with an optional Gaussian (MAP) prior.
///
/// The model (docs/belief.md has it in full): the ball centre's horizontal position p and
/// velocity v on the surface offset by the ball radius (G(p): its gradient, the lane's at the
/// ball's foot point plus the tilt s; q^2 = 1 + |G|^2; u = H v, H = dG/dp), with the world's soft
/// ground contact as a state of its own (the ball sunk by -e, MuJoCo's soft constraint with the
/// world's solref/solimp: the normal force N lags the curvature's demand by ~20 ms) and the spin
/// about the surface normal W = r w_n (a diagonal roll over a curved lane spins the ball up and
/// the spin pushes it sideways):
///   dv/dt = -(G / q) [N - g/q + g / ((1 + beta) q)] - rho N (r/l) / (1 + beta) v / |v_3d|
///           + beta / (1 + beta) W (u_y, -u_x) / q^2,   l = r + e/2, beta = 0.4 (r/l)^2
/// On a plane it is Penner's dv/dt = -(5/7) g [kR rho v/|v| + kS (grad z + s)]. RK4 in steps of
/// at most 10 ms between the samples, refined where the acceleration jumps (deterministic).
#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

#include "field/field.hpp"

namespace mg::belief {

/// [m/s^2] gravity, as the simulated world's (src/sim).
inline constexpr double kGravity = 9.81;
/// The MuJoCo world's rolling ball decelerates by (5/7) rho g x kR: its soft ground contact sinks
/// the ball 0.37 mm, so friction acts a lever l = r - 0.19 mm below the centre (tests/sim/
/// test_fast_putt.cpp: kR = (r/l) 1.4 / (1 + 0.4 (r/l)^2) = 1.0037). Measured again: fitted to
/// MuJoCo's paths on the flat lane of a plant with rho x 1.15, the model finds rho within
/// 0.001 % (tests/belief: FitGreen.RecoversAPlantFromMujocoPaths; ignoring the lever: 0.37 % high).
/// The model takes both factors from the contact's sink at each instant; these are their values at
/// rest, used where a rigid ball will do (the fit's start values, the stop test).
inline constexpr double kRollingResistanceFactor = 1.0037;
/// ... and a slope accelerates it by (5/7) g sin(theta) x kS, kS = 1.4 / (1 + 0.4 (r/l)^2) =
/// 0.9950 for the same lever (the ball's effective mass about the contact point).
inline constexpr double kSlopeFactor = 0.9950;

/// A ball path as the robot perceived it.
struct ObservedPath {
  std::vector<std::array<double, 3>> samples;  ///< (t [s] since launch, x, y [m]), t ascending
  /// Where the hole was (the path is cut near it); none: the field's hole.
  std::optional<std::array<double, 2>> hole;
};

/// The fit's prior (MAP): rolling resistance rho and tilt (dz/dx, dz/dy) with their std; an
/// infinite std is no prior on that parameter. The prior's values also anchor the fit's start
/// values (rolling_resistance <= 0: the survey's rho).
struct GreenPrior {
  double rolling_resistance = 0.0;
  std::array<double, 2> extra_slope{};
  std::array<double, 3> std{std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::infinity(),
                            std::numeric_limits<double>::infinity()};
};

/// A rolling ball's state: centre (x, y) [m], velocity (vx, vy) [m/s], world frame, and its
/// spin about the surface normal as W = ball radius x spin [m/s] (counter-clockwise seen from
/// above; only a curved lane turns it into a sideways push).
struct RollState {
  double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0;
  double spin = 0.0;
};

/// [m/s] The prior std of a path's spin W at the start of its rolling part (mean 0): the spin a
/// curved lane gives a ball over its slide, and a club's side spin, are of this order (W =
/// 0.05 m/s is 2.3 rad/s).
inline constexpr double kSpinPriorStd = 2.0;

/// How one path entered the fit.
struct PathFit {
  bool used = false;      ///< it had enough rolling samples
  std::size_t first = 0;  ///< its samples [first, last) were fitted
  std::size_t last = 0;
  RollState start;            ///< the fitted state at samples[first]'s time
  double rms_residual = 0.0;  ///< [m] per axis
};

/// One fitted sample: where the ball was seen, and the seen position minus the fitted model's.
struct SampleResidual {
  int path = 0;                      ///< index into the fitted paths
  int run = 0;                       ///< the path's rolling run (0: the first; see rolling_spans)
  double t = 0.0, x = 0.0, y = 0.0;  ///< [s], [m] as perceived
  double dx = 0.0, dy = 0.0;         ///< [m] perceived - model
  std::array<double, 2> heading{1.0, 0.0};  ///< the model ball's direction of motion
};

struct GreenEstimate {
  double rolling_resistance = 0.0;      ///< rho [-] (absolute)
  std::array<double, 2> extra_slope{};  ///< (dz/dx, dz/dy) [-] on top of the surveyed surface
  std::array<double, 3> std{};          ///< std of rho, slope x, slope y (inf: not determined)
  int paths_used = 0;
  int samples_used = 0;
  double rms_residual = 0.0;   ///< [m] per axis, over the fitted samples
  int iterations = 0;          ///< Levenberg-Marquardt steps taken
  std::vector<PathFit> paths;  ///< one per input path
  /// Every fitted sample's residual, path by path and run by run in time order
  /// (belief/residuals.hpp reads them for what the model leaves out).
  std::vector<SampleResidual> residuals;
};

/// The green's unknowns.
struct GreenParams {
  double rolling_resistance = 0.131;
  std::array<double, 2> extra_slope{};
};

/// The model ball's positions (x, y) [m] at `times` [s] (ascending), starting from `start` at
/// times[0] on `surveyed` tilted by green.extra_slope with rho = green.rolling_resistance.
/// Deterministic; for tests and for predicting a roll.
std::vector<std::array<double, 2>> predict_roll(const field::Field& surveyed,
                                                const GreenParams& green, const RollState& start,
                                                const std::vector<double>& times);

/// The samples of `path` that show the ball rolling on the open lane, [first, last): from the
/// end of the slide (t* = 2 v0 / (7 mu g) after the first sample, mu the field's sliding
/// friction, v0 the first samples' speed; times 1.3 plus 0.05 s, for a grass slower than the
/// survey's) to the first sample within (ball radius + 2 cm) of a border or obstacle, within
/// (hole radius + ball radius + 1 cm) of the hole, where it would stop within 0.3 s (at 1.25
/// times the survey's rho, up the surveyed slope: about 0.35 m/s on a level lane; a ball about
/// to stall on a slope may roll back, which the fit cannot follow), or where it may hop (a crest
/// taken so fast that the normal force falls under half the weight).
std::array<std::size_t, 2> rolling_span(const field::Field& surveyed, const ObservedPath& path);

/// Every rolling run of `path` of at least kMinSamples samples: the first as rolling_span's,
/// then, where a run ended at a possible hop or slip over a crest (not at a border, an obstacle,
/// the hole or a stop), the next one from 0.1 s later, and so on. A putt over bumps is then
/// read on both sides of each.
std::vector<std::array<std::size_t, 2>> rolling_spans(const field::Field& surveyed,
                                                      const ObservedPath& path);

/// Fits rho and the tilt to the rolling part of `paths` (MAP with `prior`; each path's start
/// state is fitted too, its spin with the prior kSpinPriorStd): the samples' vision
/// error is `vision_noise` [m] std per axis, or, if 0, estimated from the residuals. The std of
/// the result is the Gauss-Newton covariance's. Deterministic. Throws InputError for a
/// non-finite sample, times not ascending or a negative vision noise, NumericalError when no
/// path has enough rolling samples.
/// `every_run`: each path's every rolling run (rolling_spans, each with its own start state);
/// false: its first (rolling_span).
GreenEstimate fit_green(const field::Field& surveyed, const std::vector<ObservedPath>& paths,
                        const GreenPrior& prior, double vision_noise, bool every_run = false);

}  // namespace mg::belief
