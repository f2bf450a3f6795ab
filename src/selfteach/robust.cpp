#include "selfteach/robust.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "belief/prior.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "selfteach/hindsight.hpp"
#include "system/observe.hpp"
#include "teacher/teacher.hpp"

namespace mg::selfteach {
namespace {

constexpr double kCentredCapture =
    1.69;  ///< [m/s] centred lip-out, 108 mm x 60 mm cup (docs/physics.md)

std::array<double, 2> region_centre(const field::Situations& region) {
  const auto b = region_bounds(region);
  return {0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3])};
}

}  // namespace

LaunchNoise measure_launch_noise(const system::System& system, const field::Situations& region,
                                 double torque_noise, double position_std, int putts,
                                 std::uint64_t seed) {
  if (putts < 2 || putts > 10000)
    throw InputError(fmt::format("noise measurement: putts: expected 2..10000, got {}", putts));
  if (!(torque_noise >= 0.0 && torque_noise <= 0.1))
    throw InputError(
        fmt::format("noise measurement: torque noise: expected 0..0.1, got {}", torque_noise));
  if (!(position_std >= 0.0 && position_std <= 0.1))
    throw InputError(
        fmt::format("noise measurement: position std: expected 0..0.1 m, got {}", position_std));
  const auto& f = system.field();
  const auto hole = region_centre(region);
  const auto guess = belief::prior_launch(f, hole, 0.4);
  const double speed = region.learn_speed ? std::clamp(guess.speed / 1.6, system.config().speed_min,
                                                       system.config().speed_max)
                                          : region.speed;
  system::SystemData data(system);
  std::vector<double> angles, speeds;
  for (int k = 0; k < putts; ++k) {
    control::FullPuttOptions o;
    o.seed = derive_seed(seed, static_cast<std::uint64_t>(k));
    control::PlantEffectValues noise;
    noise.torque_noise = torque_noise;
    // Cameras of its own read the launch from the path they saw.
    if (system::paths_seen_by_perception(system)) o.record_interval = 0.01;
    // The hole off the lane's line of play: the launch is what is measured.
    auto r = system::arm_putt(system, data, hole, guess.angle, speed, o, noise);
    if (!r.hit) continue;
    system::perceive_putt(system, data, r);
    if (!std::isfinite(r.launch.speed)) continue;  // the cameras did not see it
    angles.push_back(r.launch.angle);
    speeds.push_back(r.launch.speed);
  }
  LaunchNoise n;
  n.putts = putts;
  n.position_std = position_std;
  const auto stats = [](const std::vector<double>& v) {
    double m = 0.0, s = 0.0;
    for (double x : v) m += x;
    m /= static_cast<double>(v.size());
    for (double x : v) s += (x - m) * (x - m);
    return std::array<double, 2>{
        m, std::sqrt(s / static_cast<double>(std::max<std::size_t>(1, v.size() - 1)))};
  };
  if (angles.size() >= 2) {
    n.angle_std = stats(angles)[1];
    const auto sp = stats(speeds);
    n.speed_rel_std = sp[0] > 0.0 ? sp[1] / sp[0] : 0.0;
  }
  return n;
}

double sink_probability(const field::Field& field, double distance, double arrival,
                        const LaunchNoise& noise, int draws, std::uint64_t seed) {
  const double a = belief::rolling_deceleration(field);
  const double radius = 0.5 * field.hole.diameter, ball = field.ball.radius;
  const double capture = kCentredCapture * std::clamp(field.hole.depth / 0.06, 0.5, 1.0);
  // The rolling speed at launch that arrives at `arrival` after `distance` (flat approximation).
  const double rolling2 = arrival * arrival + 2.0 * a * distance;
  Rng rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  int sunk = 0;
  for (int k = 0; k < draws; ++k) {
    const double dtheta = noise.angle_std * n(rng), du = noise.speed_rel_std * n(rng);
    const double e_lat = noise.position_std * std::sqrt(2.0) * n(rng);  // hole and ball errors
    const double e_along = noise.position_std * std::sqrt(2.0) * n(rng);
    const double b = distance * dtheta + e_lat;
    const double s2 = arrival * arrival + 2.0 * rolling2 * du + 2.0 * a * e_along;
    if (s2 <= -2.0 * a * (radius - ball)) continue;  // stopped short of the opening
    if (std::abs(b) >= radius) continue;
    const double vc = capture * std::sqrt(1.0 - (b / radius) * (b / radius));
    if (s2 < vc * vc) ++sunk;
  }
  return static_cast<double>(sunk) / draws;
}

double robust_arrival_speed(const field::Field& field, const field::Situations& region,
                            const LaunchNoise& noise) {
  const auto c = region_centre(region);
  const double distance = std::hypot(c[0] - field.tee[0], c[1] - field.tee[1]);
  double best = 0.2, best_p = -1.0;
  for (int k = 0; k <= 20; ++k) {
    const double s = 0.2 + 0.05 * k;
    const double p = sink_probability(field, distance, s, noise);
    if (p > best_p + 1e-12) {
      best_p = p;
      best = s;
    }
  }
  return best;
}

}  // namespace mg::selfteach
