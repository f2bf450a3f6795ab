// The module's model and data, and the user update (requests between ticks): not real-time
// code except where noted in control/minigolf_module.hpp.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "control/minigolf_module.hpp"
#include "core/error.hpp"

namespace mg::control {

using robot::Vector7;

void fir_reset(FirFilter& f, int taps, const Vector7& value) {
  f.taps = std::clamp(taps, 1, FirFilter::kMaxTaps);
  for (auto& b : f.buffer) b = value;
  f.sum = value * static_cast<double>(f.taps);
  f.head = 0;
}

Vector7 fir_step(FirFilter& f, const Vector7& input) {
  // Running sum: subtract the sample leaving the window, add the new one.
  auto& slot = f.buffer[static_cast<std::size_t>(f.head)];
  f.sum += input - slot;
  slot = input;
  f.head = (f.head + 1) % f.taps;
  return f.sum / static_cast<double>(f.taps);
}

ModuleModel::ModuleModel(robot::ArmModel arm, ds::HittingModel hitting,
                         const ControllerConfig& config, double ball_radius)
    : config_(config), arm_(std::move(arm)), hitting_(std::move(hitting)) {
  config_.validate();
  if (!(ball_radius > 0.0 && ball_radius < 1.0))
    throw InputError(fmt::format("module: ball radius: expected 0..1 m, got {}", ball_radius));
  ball_radius_ = ball_radius;
  ik_.dt = config_.core_period();
  speed_cap_ = config_.speed_max;
  dynamic_cap_ = std::min(config_.speed_max, config_.arm_speed_cap);
  rest_speed_ = config_.rest_speed;
  rest_turn_rate_ = config_.rest_turn_rate;
  if (config_.mode == ModuleMode::kNormal) {
    speed_cap_ = std::min(speed_cap_, robot::kSafeEndpointSpeed);
    dynamic_cap_ = std::min(dynamic_cap_, speed_cap_);
    ik_.velocity_scale = 0.5;
    rest_speed_ *= 0.5;  // thesis 4.2.1: the real arm goes to the rest pose more slowly
    rest_turn_rate_ *= 0.5;
  }
  ik_.validate();
  for (int j = 0; j < 7; ++j) posture_[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
}

double ModuleModel::club_speed_cap(double angle) const {
  if (!(angle < 0.0)) return dynamic_cap_;
  const double u = std::min(1.0, -angle / config_.negative_cap_angle);
  const double cap =
      config_.arm_speed_cap + u * (config_.arm_speed_cap_negative - config_.arm_speed_cap);
  return std::min(dynamic_cap_, cap);
}

ModuleData::ModuleData(const ModuleModel& model) : ds(model.hitting()) {}

namespace {

Eigen::Vector3d direction_of(double angle) { return {std::cos(angle), std::sin(angle), 0.0}; }

bool envelope_ok(const ModuleModel& model, double angle, double speed) {
  const auto& c = model.config();
  return std::isfinite(angle) && std::isfinite(speed) && angle >= c.angle_min &&
         angle <= c.angle_max && speed >= c.speed_min && speed <= model.speed_cap();
}

}  // namespace

void module_reset(const ModuleModel& model, ModuleData& data, const Vector7& q) {
  data.state = ModuleState::kIdle;
  data.pending = Command::kNone;
  data.request_valid = false;
  data.tick = 0;
  data.time_in_state = 0.0;
  data.q_ref = q;
  data.qd_des.setZero();
  data.qdd_des.setZero();
  data.integral.setZero();
  data.tau.setZero();
  data.tau_raw.setZero();
  fir_reset(data.fir, model.config().fir_length, Vector7::Zero());
  data.at_rest_pose = false;
  data.ball_hit = false;
  data.hit_evidence = HitEvidence::kNone;
  data.ball_at_hit_start = {0, 0, 0};
  data.hit_start_tick = 0;
  data.compute_fault = false;
  data.overrun_fault = false;
  data.hook_fault = false;
  data.v_ds.setZero();
  data.seen = {};
  data.seen_tick = -1;
  data.last = {};
}

Eigen::Vector3d rest_face_position(const ModuleModel& model, double angle) {
  const auto& c = model.config();
  const Eigen::Vector3d offset(c.rest_offset[0], c.rest_offset[1], c.rest_offset[2]);
  const Eigen::Vector3d psi = direction_of(angle);
  return model.hitting().x_star() + ds::rotation_about_z(angle) * offset - c.club_face_offset * psi;
}

bool request_rest(const ModuleModel& model, ModuleData& data, double angle) {
  const auto& c = model.config();
  if (!std::isfinite(angle) || angle < c.angle_min || angle > c.angle_max) return false;
  if (angle != data.angle) data.at_rest_pose = false;  // a new target: not there yet
  data.angle = angle;
  data.pending = Command::kRest;
  return true;
}

bool request_hit(const ModuleModel& model, ModuleData& data, double angle, double speed) {
  data.pending = Command::kHit;
  data.request_valid = false;
  if (!envelope_ok(model, angle, speed)) return false;
  // A hit starts from the rest pose of its own angle: another angle is refused (not at rest).
  if (std::abs(angle - data.angle) > 1e-9) return false;
  ds::HittingCommand cmd;
  cmd.angle = angle;
  // Above what the arm tracks at this angle the DS is asked for the cap itself (a capped DS
  // velocity with the original speed profile struck the ball off-centre).
  cmd.speed = std::min(speed, model.club_speed_cap(angle));
  cmd.modulator = ds::Modulator::kSine;
  cmd.start =
      rest_face_position(model, angle) + model.config().club_face_offset * direction_of(angle);
  try {
    data.ds.set_command(model.hitting(), cmd);
  } catch (const Error&) {
    return false;
  }
  data.speed = speed;
  data.request_valid = true;
  return true;
}

void request_idle(ModuleData& data) { data.pending = Command::kIdle; }

}  // namespace mg::control
