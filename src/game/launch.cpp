#include "game/launch.hpp"

#include <cmath>
#include <random>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "system/observe.hpp"

namespace mg::game {

ArmLaunch arm_launch(const field::Field& field, std::array<double, 2> start,
                     const sim::BallState& s) {
  ArmLaunch a;
  const double vx = s.qvel[0], vy = s.qvel[1], vz = s.qvel[2];
  const double vh = std::hypot(vx, vy);
  a.angle = std::atan2(vy, vx);
  const double cx = std::cos(a.angle), cy = std::sin(a.angle);
  const auto g = field.surface.gradient(start[0], start[1]);
  const double cz = g[0] * cx + g[1] * cy;  // as sim::start_putt launches along the surface
  a.speed = vh * std::sqrt(1.0 + cz * cz);
  a.club.advance = (s.qpos[0] - start[0]) * cx + (s.qpos[1] - start[1]) * cy;
  a.club.lift = std::max(0.0, s.qpos[2] - field.height(s.qpos[0], s.qpos[1]) - field.ball.radius);
  a.club.vertical_speed = vz - cz * vh;
  // Angular velocity: body frame -> world (the orientation quaternion) -> launch frame.
  mjtNum w_body[3] = {s.qvel[3], s.qvel[4], s.qvel[5]}, w[3];
  mju_rotVecQuat(w, w_body, s.qpos.data() + 3);
  a.club.spin = {cx * w[0] + cy * w[1], -cy * w[0] + cx * w[1], w[2]};
  return a;
}

LaunchError launch_precision(const system::System& system, system::SystemData& data,
                             const std::vector<double>& club_speeds, int hits, double vision_noise,
                             std::uint64_t seed) {
  if (hits < 2) throw InputError("launch precision: expected at least 2 hits per club speed");
  Rng rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const field::Field& field = system.field();
  double angle_ss = 0.0, speed_ss = 0.0;
  int dof = 0;
  for (double club : club_speeds) {
    std::vector<ArmLaunch> got;
    for (int k = 0; k < hits; ++k) {
      control::FullPuttOptions o;
      o.seed = derive_seed(seed, static_cast<std::uint64_t>(got.size() + 1000 * dof));
      control::PlantEffectValues seen;
      seen.perceived_ball_offset = {vision_noise * normal(rng), vision_noise * normal(rng)};
      // Cameras of its own read the launch from the path they saw.
      if (system::paths_seen_by_perception(system)) o.record_interval = 0.01;
      auto r = system::arm_putt(system, data, field.hole.position, 0.0, club, o, seen);
      if (r.hit_refused || !r.hit) continue;
      system::perceive_putt(system, data, r);
      const ArmLaunch a = arm_launch(field, r.ball_start, r.launch_state);
      if (std::isfinite(a.speed)) got.push_back(a);
    }
    if (got.size() < 2) continue;
    double ma = 0.0, ms = 0.0;
    for (const auto& a : got) ma += a.angle, ms += a.speed;
    ma /= static_cast<double>(got.size()), ms /= static_cast<double>(got.size());
    for (const auto& a : got) {
      angle_ss += (a.angle - ma) * (a.angle - ma);
      speed_ss += (a.speed / ms - 1.0) * (a.speed / ms - 1.0);
    }
    dof += static_cast<int>(got.size()) - 1;
  }
  if (dof == 0) throw NumericalError(fmt::format("{}: no two hits at one club speed", field.name));
  return {std::sqrt(angle_ss / dof), std::sqrt(speed_ss / dof)};
}

}  // namespace mg::game
