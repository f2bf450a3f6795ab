// The module's robot and core updates (real-time: no allocation, no throw).
#include "control/minigolf_module.hpp"

#include "control/module_stages.hpp"

#include <algorithm>
#include <cmath>

#include "robot/dynamics.hpp"

namespace mg::control {

using robot::Vector7;

namespace {

constexpr double kEps = 1e-12;

Eigen::Vector3d direction_of(double angle) { return {std::cos(angle), std::sin(angle), 0.0}; }

bool finite(const Vector7& v) { return v.allFinite(); }

double wrap_angle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

/// Moves `from` toward `to` by at most `step` [m].
Eigen::Vector3d approach(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double step) {
  const Eigen::Vector3d d = to - from;
  const double n = d.norm();
  return n <= step ? to : Eigen::Vector3d(from + d * (step / n));
}

/// Enters a state: resets what the new state integrates from.
void enter_state(const ModuleModel& model, ModuleData& data, ModuleState next) {
  const auto& c = model.config();
  const Eigen::Isometry3d face = robot::dh_club_pose(model.arm(), data.q_ref);
  data.time_in_state = 0.0;
  switch (next) {
    case ModuleState::kIdle:
      break;
    case ModuleState::kRest:
      data.setpoint = face.translation();
      data.setpoint_heading = std::atan2(face.linear()(1, 0), face.linear()(0, 0));
      data.at_rest_pose = false;
      break;
    case ModuleState::kHitting: {
      const Eigen::Vector3d psi = direction_of(data.angle);
      data.p_ref = face.translation() + c.club_face_offset * psi;
      data.ball_hit = false;
      data.hit_evidence = HitEvidence::kNone;
      data.ball_at_hit_start = data.seen.ball;
      data.hit_start_tick = data.tick;
      data.v_ds.setZero();
      data.v_ref.setZero();
      break;
    }
    case ModuleState::kBraking:
      data.setpoint = face.translation();
      data.setpoint_heading = std::atan2(face.linear()(1, 0), face.linear()(0, 0));
      data.v_brake0 = data.state == ModuleState::kHitting ? data.v_ref : Eigen::Vector3d::Zero();
      break;
  }
}

}  // namespace

namespace {

/// Takes a perception sample: the module acts on the latest one.
void take_perception(const ModuleModel& model, ModuleData& data,
                     const perception::Perceived& seen) {
  data.seen = seen;
  // Age counts from the observation, not from this update.
  if (seen.fresh)
    data.seen_tick =
        data.tick - std::llround(std::max(0.0, seen.age) / model.config().core_period());
}

}  // namespace

bool club_reaches_ball(const ModuleModel& model, const Eigen::Isometry3d& face,
                       const std::array<double, 3>& ball) noexcept {
  // The ball centre in the face frame; the head is the box behind the face: x in [-thickness, 0],
  // |y| <= length / 2, |z| <= height / 2. Touching: the centre within one radius of the box.
  // In front of the face only the face counts; behind it (x < 0) the head has gone through
  // the ball's place, which counts as reached too (the club's path past the ball).
  const robot::ClubGeometry& club = model.arm().mount().club;
  const Eigen::Vector3d r = face.inverse() * Eigen::Vector3d(ball[0], ball[1], ball[2]);
  if (!r.allFinite()) return false;
  const double dx = std::max(0.0, r.x());
  const double dy = std::max(0.0, std::abs(r.y()) - 0.5 * club.head_length);
  const double dz = std::max(0.0, std::abs(r.z()) - 0.5 * club.head_height);
  const double radius = model.ball_radius();
  return dx * dx + dy * dy + dz * dz < radius * radius;
}

void robot_update(const ModuleModel& model, ModuleData& data,
                  const perception::Perceived& seen) noexcept {
  take_perception(model, data, seen);
  if (data.state != ModuleState::kHitting) return;
  const auto& h = model.hitting();
  // Past the hitting plane the DS keeps commanding the hitting velocity (notes/ds.md).
  data.v_ds = ds::ball_reached(h, data.ds, data.p_ref, 0.05)
                  ? ds::hitting_velocity(h, data.ds)
                  : ds::hitting_ds_velocity(h, data.ds, data.p_ref);
  const double n = data.v_ds.norm();
  if (!std::isfinite(n)) {
    data.v_ds.setZero();
  } else if (n > model.club_speed_cap(data.angle)) {
    data.v_ds *= model.club_speed_cap(data.angle) / n;  // what the arm can track / the mode's rule
  }
}

bool perception_fresh(const ModuleModel& model, const ModuleData& data) {
  if (data.seen_tick < 0) return false;
  const double age = static_cast<double>(data.tick - data.seen_tick) * model.config().core_period();
  return age <= model.config().perception_max_age;
}

bool ball_in_place(const ModuleModel& model, const ModuleData& data) {
  const Eigen::Vector3d& x = model.hitting().x_star();
  return std::hypot(data.seen.ball[0] - x.x(), data.seen.ball[1] - x.y()) <=
         model.config().ball_tolerance;
}

namespace {

bool measurable(const MeasuredState& m) { return finite(m.q) && finite(m.qd); }

double max_joint_speed(const Vector7& qd) {
  double qd_max = 0.0;
  for (int j = 0; j < 7; ++j) qd_max = std::max(qd_max, std::abs(qd[j]));
  return qd_max;
}

}  // namespace

Observation observe(const ModuleModel& model, ModuleData& data,
                    const MeasuredState& measured) noexcept {
  const auto& c = model.config();
  const auto& arm = model.arm();
  const Vector7& q = measured.q;
  const Vector7& qd = measured.qd;
  if (measured.perception) robot_update(model, data, *measured.perception);

  Observation obs;
  obs.command = data.pending;
  data.pending = Command::kNone;
  obs.request_valid = data.request_valid;
  obs.perception_fresh = perception_fresh(model, data);
  obs.ball_in_place = ball_in_place(model, data);
  bool fault = data.compute_fault || data.overrun_fault || data.hook_fault || !finite(q) ||
               !finite(qd) || !finite(data.q_ref);
  if (!fault) {
    for (int j = 0; j < 7; ++j) {
      if (q[j] < arm.position_lower()[j] - 0.02 || q[j] > arm.position_upper()[j] + 0.02 ||
          std::abs(qd[j]) > c.velocity_fault_factor * arm.velocity_limit()[j])
        fault = true;
    }
  }
  if (data.state == ModuleState::kHitting && data.time_in_state > c.max_hit_duration) fault = true;
  // Lost ball: no fresh perception while the club is on its way to the ball.
  if (data.state == ModuleState::kHitting && !data.ball_hit && !obs.perception_fresh) fault = true;
  obs.fault = fault;
  const double qd_max = max_joint_speed(qd);
  obs.joints_stationary =
      finite(qd) && qd_max < c.stationary_threshold && data.time_in_state >= c.brake_time;
  obs.at_rest_pose =
      data.state == ModuleState::kRest && data.at_rest_pose && qd_max < c.stationary_threshold;
  if (data.state == ModuleState::kHitting) {
    // Hit detection from what a real system measures: the club head by FK of the measured
    // joints against the perceived ball, and the perceived ball's motion since the hit began.
    if (!data.ball_hit && finite(q) &&
        club_reaches_ball(model, robot::dh_club_pose(arm, q), data.seen.ball)) {
      data.ball_hit = true;
      data.hit_evidence = HitEvidence::kClubPath;
    }
    if (!data.ball_hit && data.seen.fresh && data.seen_tick >= data.hit_start_tick) {
      const auto& b = data.seen.ball;
      const auto& b0 = data.ball_at_hit_start;
      if (std::hypot(b[0] - b0[0], b[1] - b0[1]) > c.ball_moved_distance) {
        data.ball_hit = true;
        data.hit_evidence = HitEvidence::kBallMotion;
      }
    }
    obs.ball_hit = data.ball_hit;
    const Eigen::Vector3d psi = direction_of(data.angle);
    obs.passed_ball = (data.p_ref - model.hitting().x_star()).dot(psi) > c.passed_distance;
  }
  return obs;
}

Reason transition(const ModuleModel& model, ModuleData& data, const Observation& observation,
                  const Vector7& q) noexcept {
  const Transition tr = next_state(data.state, observation);
  if (tr.next != data.state) {
    enter_state(model, data, tr.next);
    data.state = tr.next;
  }
  // Idle (and a fault with a broken measurement) restart the reference from the measurement.
  if (data.state == ModuleState::kIdle || !finite(data.q_ref)) {
    data.q_ref = finite(q) ? q : Vector7::Zero();
  }
  return tr.reason;
}

robot::FaceTarget reference(const ModuleModel& model, ModuleData& data,
                            const MeasuredState& measured) noexcept {
  const auto& c = model.config();
  const auto& arm = model.arm();
  const double dt = c.core_period();
  robot::FaceTarget target;
  if (data.state == ModuleState::kRest) {
    const Eigen::Vector3d goal = rest_face_position(model, data.angle);
    data.setpoint = approach(data.setpoint, goal, model.rest_speed() * dt);
    const double dh = wrap_angle(data.angle - data.setpoint_heading);
    const double turn = model.rest_turn_rate() * dt;
    data.setpoint_heading += std::clamp(dh, -turn, turn);
    target.position = data.setpoint;
    target.heading = data.setpoint_heading;
    const Eigen::Isometry3d face = robot::dh_club_pose(arm, measured.q);
    const double heading = std::atan2(face.linear()(1, 0), face.linear()(0, 0));
    data.at_rest_pose = (face.translation() - goal).norm() < c.rest_tolerance &&
                        std::abs(wrap_angle(heading - data.angle)) < c.rest_heading_tolerance &&
                        (data.setpoint - goal).norm() < kEps &&
                        max_joint_speed(measured.qd) < c.stationary_threshold;
  } else if (data.state == ModuleState::kHitting) {
    // The DS is evaluated at the reference face (FK of q_ref), not at an integrated point: when
    // a joint saturates, the club just gets there later instead of a set-point running away.
    const Eigen::Vector3d psi = direction_of(data.angle);
    const Eigen::Vector3d face_ref = robot::dh_club_pose(arm, data.q_ref).translation();
    const Eigen::Vector3d p_kin = face_ref + c.club_face_offset * psi;
    // The DS point is integrated (a smooth reference) but kept on a leash to the kinematic
    // reference: when a joint saturates the club gets there later instead of the set-point
    // running away.
    const Eigen::Vector3d lead = data.p_ref - p_kin;
    if (lead.norm() > c.reference_leash)
      data.p_ref = p_kin + lead * (c.reference_leash / lead.norm());
    // Smoothstep ramp-in: the DS asks for full speed at once, the arm starts from rest.
    const double u = std::min(1.0, data.time_in_state / c.hit_ramp_time);
    const Eigen::Vector3d v_ref = data.v_ds * (u * u * (3.0 - 2.0 * u));
    data.v_ref = v_ref;
    data.p_ref += v_ref * dt;
    target.position = data.p_ref - c.club_face_offset * psi;
    target.heading = data.angle;
    target.velocity.head<3>() = v_ref;
  } else if (data.state == ModuleState::kBraking) {
    // The face velocity ramps to zero while the club is lifted.
    const double t = data.time_in_state;
    const double s = std::max(0.0, 1.0 - t / c.brake_time);
    Eigen::Vector3d v = data.v_brake0 * s;
    if (t < c.brake_time)
      v.z() +=
          c.brake_lift_height * (M_PI / (2.0 * c.brake_time)) * std::sin(M_PI * t / c.brake_time);
    data.setpoint += v * dt;
    target.position = data.setpoint;
    target.heading = data.setpoint_heading;
    target.velocity.head<3>() = v;
  }
  return target;
}

robot::RtStatus track(const ModuleModel& model, ModuleData& data,
                      const robot::FaceTarget& target) noexcept {
  const double dt = model.config().core_period();
  Vector7 qd_ik;
  const robot::RtStatus status =
      robot::track_face(model.arm(), data.q_ref, target, model.posture(), model.ik(), qd_ik);
  if (status == robot::RtStatus::kInvalidInput) qd_ik.setZero();
  const Vector7 qd_prev = data.qd_des;
  data.qd_des = fir_step(data.fir, qd_ik);
  data.qdd_des = (data.qd_des - qd_prev) / dt;
  data.q_ref += data.qd_des * dt;
  return status;
}

void hold(const ModuleModel& model, ModuleData& data, const MeasuredState& measured) noexcept {
  if (measurable(measured) && data.state == ModuleState::kIdle) {
    fir_reset(data.fir, model.config().fir_length, Vector7::Zero());
    data.integral.setZero();
  }
  data.qd_des.setZero();
  data.qdd_des.setZero();
}

TorqueOutput torque(const ModuleModel& model, ModuleData& data,
                    const MeasuredState& measured) noexcept {
  const auto& c = model.config();
  const auto& arm = model.arm();
  const double dt = c.core_period();
  const Vector7& q = measured.q;
  const Vector7& qd = measured.qd;
  TorqueOutput out;
  Vector7 tau = Vector7::Zero();
  if (!measurable(measured)) {
    // Nothing to compute torques from: zero torque (the plant's brakes would engage).
  } else if (data.state == ModuleState::kIdle) {
    if (robot::gravity_torque(arm, q, tau) != robot::RtStatus::kOk) tau.setZero();
  } else {
    // Computed-torque PID: gains in acceleration units, multiplied by M(q) through the RNEA.
    const Vector7 e = data.q_ref - q;
    Vector7 a = data.qdd_des;
    for (int j = 0; j < 7; ++j) {
      const auto i = static_cast<std::size_t>(j);
      data.integral[j] =
          std::clamp(data.integral[j] + e[j] * dt, -c.integral_limit, c.integral_limit);
      a[j] += c.kp[i] * e[j] + c.ki[i] * data.integral[j] + c.kd[i] * (data.qd_des[j] - qd[j]);
    }
    if (robot::inverse_dynamics(arm, q, qd, a, tau) != robot::RtStatus::kOk) {
      out.failed = true;
      if (robot::gravity_torque(arm, q, tau) != robot::RtStatus::kOk) tau.setZero();
    }
  }
  data.tau_raw = tau;
  for (int j = 0; j < 7; ++j) {
    const double lim = arm.torque_limit()[j];
    if (!std::isfinite(tau[j])) tau[j] = 0.0;
    if (std::abs(tau[j]) > lim) out.clamped = true;
    tau[j] = std::clamp(tau[j], -lim, lim);
  }
  data.tau = tau;
  out.tau = tau;
  return out;
}

ModuleCommand module_update(const ModuleModel& model, ModuleData& data,
                            const MeasuredState& measured) noexcept {
  TickInfo info;
  const Observation obs = observe(model, data, measured);
  bool fault = obs.fault;
  info.reason = transition(model, data, obs, measured.q);
  if (measurable(measured) && data.state != ModuleState::kIdle) {
    info.ik_status = track(model, data, reference(model, data, measured));
    // A failed IK brakes on the next tick (braking itself goes on with a zero IK velocity).
    if (info.ik_status == robot::RtStatus::kInvalidInput && data.state != ModuleState::kBraking)
      fault = true;
  } else {
    hold(model, data, measured);
  }
  const TorqueOutput out = torque(model, data, measured);
  if (out.failed) fault = true;
  info.torque_clamped = out.clamped;
  info.fault = fault;
  info.hit = data.hit_evidence;
  data.last = info;
  // A fault found while computing (IK/RNEA) is reported in the next tick's observation.
  data.compute_fault = fault && !obs.fault;
  data.time_in_state += model.config().core_period();
  ++data.tick;
  ModuleCommand command;
  command.tau = out.tau;
  command.state = data.state;
  command.status = info;
  return command;
}

ModuleCommand control_tick(const ModuleModel& model, ModuleData& data,
                           ArmBackend& backend) noexcept {
  const ModuleCommand command = module_update(model, data, backend.read());
  backend.write(command);
  return command;
}

}  // namespace mg::control
