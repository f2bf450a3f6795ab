#include "experiments/identify.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "field/situations.hpp"
#include "system/observe.hpp"

namespace mg::experiments {
namespace {

/// The survey's spread when nothing better is known: grass varies by +-20 %, a survey misses a
/// tilt of +-0.5 % (docs/reality.md); twice that, so that the data decide.
constexpr double kSurveyRhoSpread = 0.25;
constexpr double kSurveySlopeSpread = 0.01;
/// Launch speed / club speed of the arm's putts (docs/control.md: 1.56-1.60).
constexpr double kLaunchRatio = 1.58;
/// [rad] The plan's directions off the lane's axis, changing every 4 putts: wide (the slope along
/// the lane bends these paths, and slows them less than the narrow ones: rolling resistance and
/// that slope part) and narrow (long rolls).
constexpr std::array<double, 3> kWideAngles{0.6, 0.5, 0.7}, kNarrowAngles{0.12, 0.06, 0.18};

/// [s] The launch window's end (launch_window) and the roll simulated when only the contact is
/// read.
constexpr double kLaunchWindowEnd = 0.5;
constexpr double kContactOnly = 0.05;

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// A Gaussian draw (Box-Muller on 53-bit uniforms: the same on every platform).
double gaussian(Rng& rng) {
  const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
}

/// Inverse-variance combination of a prior (mean, std; std <= 0 or inf: none) and a fit.
std::array<double, 2> combine(double prior, double prior_std, double fit, double fit_std) {
  const bool has_prior = prior_std > 0.0 && std::isfinite(prior_std);
  const bool has_fit = fit_std > 0.0 && std::isfinite(fit_std);
  if (!has_prior) return {fit, fit_std};
  if (!has_fit)
    return std::isfinite(fit_std) ? std::array<double, 2>{fit, fit_std}
                                  : std::array<double, 2>{prior, prior_std};
  const double wp = 1.0 / (prior_std * prior_std), wf = 1.0 / (fit_std * fit_std);
  return {(wp * prior + wf * fit) / (wp + wf), 1.0 / std::sqrt(wp + wf)};
}

/// A finite positive std, else 0 (the file's "not estimated").
double file_std(double v) { return std::isfinite(v) && v > 0.0 ? v : 0.0; }

/// True when (x, y) is within the fit's clearances of a border, an obstacle or the hole.
bool near_an_edge(const field::Field& f, std::array<double, 2> hole, double x, double y) {
  const double r = f.ball.radius;
  const auto& b = f.bounds;
  if (std::min({x - b[0], b[1] - x, y - b[2], b[3] - y}) < r + 0.02) return true;
  for (const auto& o : f.obstacles)
    if (o.distance({x, y}) < r + 0.02) return true;
  return std::hypot(x - hole[0], y - hole[1]) < 0.5 * f.hole.diameter + r + 0.01;
}

}  // namespace

std::vector<IdentifyHit> plan_identification(const system::System& own, int putts,
                                             const std::string& balls, std::uint64_t seed) {
  if (putts < 1) throw InputError(fmt::format("identify: --putts: expected >= 1, got {}", putts));
  const field::Field& f = own.field();
  const std::array<double, 2> hole = f.hole.position;
  std::vector<std::array<double, 2>> starts;
  if (balls.empty()) {
    starts.assign(static_cast<std::size_t>(putts), f.tee);
  } else {
    const field::Situations region = field::region_from_spec(f, "", balls);
    Rng rng(derive_seed(seed, 0x62616c6c73ULL));  // "balls"
    for (int tries = 0; tries < 100 * putts && static_cast<int>(starts.size()) < putts; ++tries) {
      const auto b = region.balls->sample(rng);
      if (field::playable(f, field::Situation(b, hole))) starts.push_back(b);
    }
    if (static_cast<int>(starts.size()) < putts)
      throw InputError(fmt::format(
          "identify: --balls '{}': found {} of {} balls that can lie at rest clear of the hole",
          balls, starts.size(), putts));
  }
  const auto& b = f.bounds;
  const double rho = f.rolling_resistance, mu = f.sliding_friction, g = belief::kGravity;
  std::vector<IdentifyHit> hits;
  for (int k = 0; k < putts; ++k) {
    const auto& ball = starts[static_cast<std::size_t>(k)];
    // + wide long, - wide short, + narrow short, - narrow long, then again: across the lane's
    // axis both ways (the slope across the path), far and near (the rolling resistance).
    const int cycle = k / 2;
    const double side = k % 2 == 0 ? 1.0 : -1.0;
    const bool wide = cycle % 2 == 0;
    const bool long_roll = (k + cycle) % 2 == 0;
    // Along the lane the longer way, and from a ball with a metre of lane both ways, every
    // other pair of putts the other way: rolls both ways part rolling resistance from the slope
    // along the lane (it slows one and speeds the other), which from the tee only the wide
    // putts' bends tell apart.
    const bool forward = ball[0] <= 0.5 * (b[0] + b[1]);
    const bool both_ways = std::min(b[1] - ball[0], ball[0] - b[0]) >= 1.0;
    const bool flip = both_ways && (k / 2 + k / 4) % 2 == 1;
    const double end = forward != flip ? b[1] : b[0];
    const double axis = std::atan2(0.5 * (b[2] + b[3]) - ball[1], end - ball[0]);
    const auto variant = static_cast<std::size_t>(k / 4 % 3);
    const double angle = axis + side * (wide ? kWideAngles[variant] : kNarrowAngles[variant]);
    // How far the ball can roll that way: to 0.1 m before a border.
    const double cx = std::cos(angle), cy = std::sin(angle);
    double reach = 1e9;
    if (cx > 0.0) reach = std::min(reach, (b[1] - 0.1 - ball[0]) / cx);
    if (cx < 0.0) reach = std::min(reach, (b[0] + 0.1 - ball[0]) / cx);
    if (cy > 0.0) reach = std::min(reach, (b[3] - 0.1 - ball[1]) / cy);
    if (cy < 0.0) reach = std::min(reach, (b[2] + 0.1 - ball[1]) / cy);
    IdentifyHit h;
    h.situation = field::Situation(ball, hole);
    h.angle = angle;
    // Slide and roll on the surveyed lane: distance = v0^2 (5/14 / (rho g) + 12/49 / (mu g)).
    const double distance = (long_roll ? 0.9 : 0.55) * std::max(reach, 0.3);
    const double v0 = std::sqrt(distance / (5.0 / 14.0 / (rho * g) + 12.0 / 49.0 / (mu * g)));
    h.speed = std::clamp(v0 / kLaunchRatio, 0.6, 2.0);
    if (!system::hit_reachable(own, h.angle, h.speed))
      throw InputError(fmt::format(
          "identify: the arm cannot make the hit at {:.3f} rad, {:.2f} m/s from ({:.2f}, {:.2f})",
          h.angle, h.speed, ball[0], ball[1]));
    h.path.hole = hole;
    hits.push_back(std::move(h));
  }
  return hits;
}

void play_identification(const system::System& truth, std::vector<IdentifyHit>& hits,
                         double vision_noise, std::uint64_t seed,
                         const std::function<void(int)>& done) {
  system::SystemData data(truth);
  // Cameras of its own see the paths with their own errors: no Gaussian noise on top.
  const double noise = system::paths_seen_by_perception(truth) ? 0.0 : vision_noise;
  for (std::size_t k = 0; k < hits.size(); ++k) {
    IdentifyHit& h = hits[k];
    control::FullPuttOptions o;
    o.record_interval = 0.01;
    control::FullPuttResult r = system::arm_hit(truth, data, h.situation, h.angle, h.speed, o);
    system::perceive_putt(truth, data, r);
    perceive_hit(h, r, noise, derive_seed(seed, k));
    if (done) done(static_cast<int>(k) + 1);
  }
}

void perceive_hit(IdentifyHit& hit, const control::FullPuttResult& result, double vision_noise,
                  std::uint64_t seed, double interval) {
  hit.hit = result.hit;
  hit.reached_speed = result.hit ? result.club.speed : 0.0;
  hit.path.samples.clear();
  Rng rng(seed);
  double next = -1.0;
  for (const sim::BallSample& s : result.outcome.trajectory) {
    if (s.t < next) continue;
    next = s.t + interval - 1e-9;
    const double ex = gaussian(rng), ey = gaussian(rng);
    hit.path.samples.push_back({s.t, s.x + vision_noise * ex, s.y + vision_noise * ey});
  }
}

belief::GreenPrior green_prior(const field::Field& surveyed,
                               const std::optional<belief::Belief>& prior) {
  belief::GreenPrior p;
  p.rolling_resistance = surveyed.rolling_resistance;
  p.std = {kSurveyRhoSpread * surveyed.rolling_resistance, kSurveySlopeSpread, kSurveySlopeSpread};
  if (!prior) return p;
  const plant::Plant& e = prior->estimate;
  const plant::Plant& s = prior->std;
  p.rolling_resistance = plant::true_rolling_resistance(surveyed, e);
  p.extra_slope = e.field.extra_slope;
  const double rho_std = s.field.rolling_resistance ? *s.field.rolling_resistance
                         : s.field.rolling_resistance_scale
                             ? *s.field.rolling_resistance_scale * surveyed.rolling_resistance
                             : 0.0;
  if (rho_std > 0.0) p.std[0] = rho_std;
  for (std::size_t i = 0; i < 2; ++i)
    if (s.field.extra_slope[i] > 0.0) p.std[i + 1] = s.field.extra_slope[i];
  return p;
}

std::array<double, 2> launch_window(const field::Field& field, const belief::ObservedPath& path) {
  constexpr double kFrom = 0.03, kTo = kLaunchWindowEnd;
  const std::array<double, 2> hole = path.hole ? *path.hole : field.hole.position;
  double to = kTo;
  double previous = kFrom;
  for (const auto& s : path.samples) {
    if (s[0] < kFrom) continue;
    if (s[0] > kTo) break;
    if (near_an_edge(field, hole, s[1], s[2])) {
      to = previous;
      break;
    }
    previous = s[0];
  }
  return {kFrom, to};
}

namespace {

/// The lane the green is fitted on: the survey with the prior's bumps (a spatial correction).
field::Field prior_shape(const field::Field& surveyed, const std::optional<belief::Belief>& prior) {
  if (!prior || prior->estimate.field.bumps.empty()) return surveyed;
  plant::Plant bumps;
  bumps.field.bumps = prior->estimate.field.bumps;
  return plant::true_field(surveyed, bumps);
}

/// The green's keys of `b` (rho absolute, the tilt, their std) and the vision's noise from `green`.
void apply_green(const belief::GreenEstimate& green, belief::Belief& b) {
  b.estimate.field.rolling_resistance = green.rolling_resistance;
  b.estimate.field.rolling_resistance_scale.reset();
  b.estimate.field.extra_slope = green.extra_slope;
  b.std.field.rolling_resistance_scale.reset();
  b.std.field.rolling_resistance = file_std(green.std[0]);
  if (*b.std.field.rolling_resistance == 0.0) b.std.field.rolling_resistance.reset();
  b.std.field.extra_slope = {file_std(green.std[1]), file_std(green.std[2])};
  // The vision's error per axis: the paths' residual (the model's own error is ~0.01 mm).
  b.estimate.perception.noise = std::min(green.rms_residual, 0.05);
  b.std.perception.noise =
      file_std(green.rms_residual / std::sqrt(2.0 * std::max(1, green.samples_used)));
}

}  // namespace

Identification identify_belief(const control::ModuleConfig& config, const field::Field& surveyed,
                               const std::vector<IdentifyHit>& hits, std::size_t n,
                               const std::optional<belief::Belief>& prior, bool every_run) {
  n = std::min(n, hits.size());
  Identification id;
  std::vector<belief::ObservedPath> paths;
  for (std::size_t k = 0; k < n; ++k) paths.push_back(hits[k].path);
  double t0 = cpu_seconds();
  id.green = belief::fit_green(prior_shape(surveyed, prior), paths, green_prior(surveyed, prior),
                               0.0, every_run);
  id.fit_cpu += cpu_seconds() - t0;

  belief::Belief& b = id.belief;
  if (prior) {
    b.estimate = prior->estimate;
    b.std = prior->std;
  }
  b.estimate.source.clear();
  b.estimate.hash.clear();
  apply_green(id.green, b);
  b.putts = (prior ? prior->putts : 0) + static_cast<int>(n);

  // The robot's own model of each hit: its arm on the lane it now believes in.
  t0 = cpu_seconds();
  const system::System own(config, belief::believed_field(surveyed, b));
  system::SystemData data(own);
  std::vector<const IdentifyHit*> used;
  for (std::size_t k = 0; k < n; ++k) {
    if (!hits[k].hit) continue;
    const IdentifyHit& h = hits[k];
    // Only the club at the contact is read: the ball's roll is not simulated.
    control::FullPuttOptions contact;
    contact.max_duration = kContactOnly;
    const control::FullPuttResult r =
        system::arm_hit(own, data, h.situation, h.angle, h.speed, contact);
    belief::ArmObservation o;
    o.commanded_speed = h.speed;
    o.reached_speed = h.reached_speed;
    o.predicted_speed = r.hit ? r.club.speed : 0.0;
    id.observations.push_back(o);
    used.push_back(&h);
  }
  id.predict_cpu += cpu_seconds() - t0;
  t0 = cpu_seconds();
  const double scale = belief::fit_arm(id.observations).club_speed_scale;
  id.fit_cpu += cpu_seconds() - t0;
  // The same hits as the arm really makes them (the speed it reaches), on the believed lane:
  // their paths bend as the perceived ones do, but for the launch's error.
  t0 = cpu_seconds();
  for (std::size_t k = 0; k < used.size(); ++k) {
    const IdentifyHit& h = *used[k];
    control::FullPuttOptions o;
    o.record_interval = 0.01;
    o.max_duration = kLaunchWindowEnd + 0.05;  // the launch window's part of the path
    const double speed = std::clamp(h.speed * scale, config.speed_min, config.speed_max);
    const control::FullPuttResult r = system::arm_hit(own, data, h.situation, h.angle, speed, o);
    if (!r.hit) continue;
    std::vector<std::array<double, 3>> predicted;
    for (const sim::BallSample& s : r.outcome.trajectory) predicted.push_back({s.t, s.x, s.y});
    const auto window = launch_window(surveyed, h.path);
    id.observations[k].observed_launch_angle =
        belief::path_direction(h.path.samples, window[0], window[1]);
    id.observations[k].predicted_launch_angle =
        belief::path_direction(predicted, window[0], window[1]);
  }
  id.predict_cpu += cpu_seconds() - t0;
  t0 = cpu_seconds();
  id.arm = belief::fit_arm(id.observations);
  id.fit_cpu += cpu_seconds() - t0;

  auto& arm = b.estimate.arm;
  const auto bias = combine(arm.launch_angle_bias, b.std.arm.launch_angle_bias,
                            id.arm.launch_angle_bias, id.arm.launch_angle_bias_std);
  const auto club = combine(arm.club_speed_scale, b.std.arm.club_speed_scale,
                            id.arm.club_speed_scale, id.arm.club_speed_scale_std);
  if (id.arm.angle_observations > 0) {
    arm.launch_angle_bias = bias[0];
    b.std.arm.launch_angle_bias = file_std(bias[1]);
  }
  if (id.arm.speed_observations > 0) {
    arm.club_speed_scale = club[0];
    b.std.arm.club_speed_scale = file_std(club[1]);
  }
  b.estimate.validate();
  belief::validate_std(b.std, "identify");
  return id;
}

Identification identify_world(const control::ModuleConfig& config, const system::System& truth,
                              int putts, const std::string& balls, std::uint64_t seed,
                              const std::optional<belief::Belief>& prior,
                              const std::function<void(int)>& done) {
  std::vector<IdentifyHit> hits = plan_identification(truth, putts, balls, seed);
  play_identification(truth, hits, truth.plant().perception.noise, seed, done);
  return identify_belief(config, truth.survey(), hits, hits.size(), prior);
}

}  // namespace mg::experiments
