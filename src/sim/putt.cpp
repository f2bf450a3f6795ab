#include "sim/putt.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"

namespace mg::sim {

void PuttRequest::validate() const {
  require_in_range("angle", angle, -3.15, 3.15);
  require_in_range("speed", speed, 1e-3, 15.0);
  require_in_range("max_duration", max_duration, 0.01, 600.0);
  require_in_range("record_interval", record_interval, 0.0, 10.0);
  if (start) {
    require_finite("start.x", (*start)[0]);
    require_finite("start.y", (*start)[1]);
  }
  require_in_range("club.advance", club.advance, -0.5, 0.5);
  require_in_range("club.lift", club.lift, 0.0, 0.2);
  require_in_range("club.vertical_speed", club.vertical_speed, -5.0, 5.0);
  for (double w : club.spin) require_in_range("club.spin", w, -2000.0, 2000.0);
}

std::string to_string(PuttEnd end) {
  switch (end) {
    case PuttEnd::kSunk:
      return "sunk";
    case PuttEnd::kAtRest:
      return "at_rest";
    case PuttEnd::kTimeOut:
      return "time_out";
    case PuttEnd::kLeftLane:
      return "left_lane";
  }
  return "unknown";
}

OutcomeTracker::OutcomeTracker(const World& world, const mjData* d, const OutcomeRules& rules)
    : OutcomeTracker(world, world.hole_position(d), rules, d->time, d->qpos + world.ids().ball_qpos,
                     d->qvel + world.ids().ball_dof) {}

OutcomeTracker::OutcomeTracker(const World& world, std::array<double, 2> hole,
                               const OutcomeRules& rules, double time, const double* position,
                               const double* velocity)
    : world_(&world), rules_(rules), hole_(hole) {
  hole_radius_ = 0.5 * world.field().hole.diameter;
  rim_z_ = world.field().height(hole_[0], hole_[1]);
  const auto& b = world.field().bounds;
  corner_z_ = world.field().height(b[0], b[2]);
  outcome_.closest_approach = 1e9;
  update(time, position, velocity);
}

void OutcomeTracker::restart(const mjData* d) {
  still_since_ = -1.0;
  inside_since_ = -1.0;
  heading_x_ = 1.0;
  heading_y_ = 0.0;
  reached_rim_ = false;
  outcome_ = PuttOutcome{};
  outcome_.closest_approach = 1e9;
  update(d);
}

double OutcomeTracker::lowest_z() {
  if (std::isnan(lowest_z_)) {
    const auto& b = world_->field().bounds;
    lowest_z_ = 1e9;
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 20; ++j)
        lowest_z_ = std::min(lowest_z_, world_->field().height(b[0] + (b[1] - b[0]) * i / 20,
                                                               b[2] + (b[3] - b[2]) * j / 20));
  }
  return lowest_z_;
}

bool OutcomeTracker::update(const mjData* d) {
  return update(d->time, d->qpos + world_->ids().ball_qpos, d->qvel + world_->ids().ball_dof);
}

bool OutcomeTracker::update(double time, const double* q, const double* v) {
  const double r = world_->field().ball.radius;
  const double dx = hole_[0] - q[0], dy = hole_[1] - q[1];
  const double dist = std::hypot(dx, dy);
  const double planar_speed = std::hypot(v[0], v[1]);
  if (planar_speed > 0.02) {
    heading_x_ = v[0] / planar_speed;
    heading_y_ = v[1] / planar_speed;
  }
  if (!reached_rim_ && (dist < outcome_.closest_approach || dist < hole_radius_)) {
    reached_rim_ = dist < hole_radius_;
    outcome_.approach_speed = planar_speed;
    outcome_.approach_lateral = heading_x_ * dy - heading_y_ * dx;
    outcome_.approach_along = reached_rim_ ? 0.0 : heading_x_ * dx + heading_y_ * dy;
  }
  outcome_.closest_approach = std::min(outcome_.closest_approach, dist);
  outcome_.duration = time;
  outcome_.rest_position = {q[0], q[1]};
  const bool over_hole = dist < hole_radius_;

  // Dropped into a deep cup: the ball's centre is well below the rim, it cannot climb out.
  if (over_hole && q[2] < rim_z_ - 0.5 * r) {
    outcome_.sunk = true;
    outcome_.end = PuttEnd::kSunk;
    return true;
  }
  // Dropped into a (shallow) cup and staying there.
  const double drop = 0.5 * std::min(world_->field().hole.depth, r);
  if (over_hole && q[2] < rim_z_ + r - drop) {
    if (inside_since_ < 0.0) inside_since_ = time;
    if (time - inside_since_ >= rules_.settle_time) {
      outcome_.sunk = true;
      outcome_.end = PuttEnd::kSunk;
      return true;
    }
  } else {
    inside_since_ = -1.0;
  }
  const auto& b = world_->field().bounds;
  // Fell below the lowest ground (corner_z_ >= lowest_z_: the grid's minimum only when needed).
  const bool fell = q[2] < corner_z_ - 0.3 && q[2] < lowest_z() - 0.3;
  if (!std::isfinite(q[0] + q[1] + q[2]) || fell || q[0] < b[0] - 0.2 || q[0] > b[1] + 0.2 ||
      q[1] < b[2] - 0.2 || q[1] > b[3] + 0.2) {
    outcome_.end = PuttEnd::kLeftLane;
    return true;
  }
  const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (speed < rules_.rest_speed) {
    if (still_since_ < 0.0) still_since_ = time;
    if (time - still_since_ >= rules_.rest_time) {
      // At rest inside a (shallow) cup counts as holed.
      outcome_.sunk = over_hole;
      outcome_.end = over_hole ? PuttEnd::kSunk : PuttEnd::kAtRest;
      return true;
    }
  } else {
    still_since_ = -1.0;
  }
  return false;
}

void start_putt(const World& world, mjData* d, std::array<double, 2> hole,
                const PuttRequest& request) {
  request.validate();
  const mjModel* m = world.model();
  world.reset(d);
  world.set_hole(d, hole);
  const auto& f = world.field();
  const auto start = request.start.value_or(f.tee);
  const auto& b = f.bounds;
  const double r = f.ball.radius;
  if (start[0] < b[0] + r || start[0] > b[1] - r || start[1] < b[2] + r || start[1] > b[3] - r)
    throw InputError(fmt::format("start: ({}, {}) is outside the lane", start[0], start[1]));
  const double cx = std::cos(request.angle), cy = std::sin(request.angle);
  const ClubLaunch& club = request.club;
  if (club.plain()) {
    world.place_ball(d, start);
  } else {  // where the club left the ball: moved along the launch, lifted
    const std::array<double, 2> at{start[0] + club.advance * cx, start[1] + club.advance * cy};
    if (at[0] < b[0] + r || at[0] > b[1] - r || at[1] < b[2] + r || at[1] > b[3] - r)
      throw InputError(fmt::format(
          "club.advance: the ball would start at ({}, {}), outside the lane", at[0], at[1]));
    world.place_ball(d, at);
    d->qpos[world.ids().ball_qpos + 2] += club.lift;
  }

  // Launch along the surface tangent in the requested horizontal direction.
  const auto g = f.surface.gradient(start[0], start[1]);
  const double cz = g[0] * cx + g[1] * cy;
  const double scale = request.speed / std::sqrt(1.0 + cz * cz);
  mjtNum* v = d->qvel + world.ids().ball_dof;
  v[0] = cx * scale;
  v[1] = cy * scale;
  v[2] = cz * scale;
  if (!club.plain()) {
    v[2] += club.vertical_speed;
    // Launch frame -> world (the ball's body frame is the world's at placement).
    v[3] = cx * club.spin[0] - cy * club.spin[1];
    v[4] = cy * club.spin[0] + cx * club.spin[1];
    v[5] = club.spin[2];
  } else if (request.rolling_start) {
    // w = n x v / r in the world frame, stored in the ball's body frame (identity at rest).
    const double inv = 1.0 / std::sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
    const double n[3] = {-g[0] * inv, -g[1] * inv, inv};
    v[3] = (n[1] * v[2] - n[2] * v[1]) / r;
    v[4] = (n[2] * v[0] - n[0] * v[2]) / r;
    v[5] = (n[0] * v[1] - n[1] * v[0]) / r;
  }
  world.update_ground_contact(d);
  mj_forward(m, d);
}

PuttOutcome simulate_putt(const World& world, mjData* d, std::array<double, 2> hole,
                          const PuttRequest& request, const OutcomeRules& rules) {
  start_putt(world, d, hole, request);
  const mjModel* m = world.model();
  OutcomeTracker tracker(world, d, rules);
  std::vector<BallSample> trajectory;
  const int record_every =
      request.record_interval > 0.0
          ? std::max(1, static_cast<int>(std::lround(request.record_interval / m->opt.timestep)))
          : 0;
  const auto record = [&] {
    const mjtNum* q = d->qpos + world.ids().ball_qpos;
    const mjtNum* w = d->qvel + world.ids().ball_dof;
    trajectory.push_back({d->time, q[0], q[1], q[2], w[0], w[1], w[2]});
  };
  if (record_every) record();
  const int max_steps = static_cast<int>(std::ceil(request.max_duration / m->opt.timestep));
  int steps = 0;
  bool decided = false;
  while (steps < max_steps && !decided) {
    world.step(d);
    ++steps;
    decided = tracker.update(d);
    if (record_every && (steps % record_every == 0 || decided)) record();
  }
  PuttOutcome out = tracker.outcome();
  out.steps = steps;
  if (!decided) out.end = PuttEnd::kTimeOut;
  out.trajectory = std::move(trajectory);
  return out;
}

}  // namespace mg::sim
