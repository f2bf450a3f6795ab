#include "system/putt.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "core/check.hpp"
#include "core/error.hpp"
#include "field/field.hpp"

namespace mg::system {

PuttReport putt(const System& sys, SystemData& data, const PuttSpec& spec) {
  PuttReport r;
  r.ball_only = spec.ball_only;
  r.hole = spec.hole ? *spec.hole : sys.field().hole.position;
  r.ball = spec.ball ? *spec.ball : sys.field().tee;
  if (spec.ball_only && spec.aim)
    throw InputError("aim: only with the arm (a ball-only putt's angle is its aim)");
  if (spec.world && (spec.aim || spec.ball_only))
    throw InputError("world: a world direction picks its own stance (not with aim or ball only)");
  // World directions are bounded like a ball-only launch angle: one turn, not any number.
  if (spec.aim) require_in_range("aim", *spec.aim, -kMaxWorldAngle, kMaxWorldAngle);
  if (spec.world) require_in_range("angle (world)", spec.angle, -kMaxWorldAngle, kMaxWorldAngle);
  if (spec.ball) check_ball_position(sys.field(), *spec.ball, "ball");
  if (spec.ball_only) {
    sim::PuttRequest request;
    request.angle = spec.angle;
    request.speed = spec.speed;
    request.max_duration = spec.max_duration;
    request.record_interval = spec.record_interval;
    request.start = spec.ball;
    request.validate();
    field::check_hole_position(sys.field(), r.hole);
    const auto real = real_hole(sys, r.hole);  // where the plant's hole really is
    field::check_hole_position(sys.ball_world().field(), real);
    r.outcome = sim::simulate_putt(sys.ball_world(), data.ball.get(), real, request);
    return r;
  }
  control::FullPuttOptions options;
  options.max_duration = spec.max_duration;
  options.record_interval = spec.record_interval;
  options.perception_source = spec.perception_source;
  control::FullPuttResult f;
  if (spec.world) {
    if (!hit_reachable(sys, spec.angle, spec.speed))
      throw InputError(fmt::format(
          "putt: no stance reaches angle {} rad at club speed {} m/s (expected a finite angle "
          "and {}..{} m/s)",
          spec.angle, spec.speed, sys.config().speed_min,
          std::min(sys.config().speed_max, sys.module().club_speed_cap())));
    r.aim = hit_pose(sys, r.ball, spec.angle, spec.speed).stance.yaw;
    f = arm_hit(sys, data, {r.ball, r.hole}, spec.angle, spec.speed, options);
  } else {
    sys.check_request(spec.angle, spec.speed, "putt");
    if (spec.ball || spec.aim) options.stance = putt_stance(sys, r.ball, r.hole, spec.aim);
    r.aim = options.stance.yaw;
    f = arm_putt(sys, data, r.hole, spec.angle, spec.speed, options);
  }
  if (f.hit_refused) throw InputError("putt: the module refused the hit request");
  if (!f.hit) throw NumericalError("putt: the club did not reach the ball");
  r.outcome = f.outcome;
  r.club = f.club;
  r.launch = f.launch;
  r.timing = f.timing;
  return r;
}

nlohmann::json putt_json(const System& sys, const PuttSpec& spec, const PuttReport& r) {
  const sim::PuttOutcome& out = r.outcome;
  nlohmann::json j = {
      {"field", sys.field().name},
      {"hole", r.hole},
      {"angle", spec.angle},
      {"speed", spec.speed},
      {"sunk", out.sunk},
      {"end", sim::to_string(out.end)},
      {"rest_position", out.rest_position},
      {"closest_approach", out.closest_approach},
      {"duration", out.duration},
      {"steps", out.steps},
      {"ball", r.ball},
  };
  j["plant"] = sys.plant().source.empty()
                   ? nlohmann::json()
                   : nlohmann::json{{"path", sys.plant().source}, {"hash", sys.plant().hash}};
  if (!r.ball_only) {
    j["aim"] = r.aim;
    j["club"] = {{"angle", r.club.angle}, {"speed", r.club.speed}};
    j["launch"] = {{"angle", r.launch.angle}, {"speed", r.launch.speed}};
    j["timing"] = {{"core_update_p99_us", r.timing.core_update_p99_us},
                   {"core_update_max_us", r.timing.core_update_max_us},
                   {"overruns", r.timing.overruns}};
  }
  return j;
}

}  // namespace mg::system
