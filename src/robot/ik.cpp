#include "robot/ik.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "core/check.hpp"
#include "core/error.hpp"

namespace mg::robot {
namespace {
constexpr double kNullRegularisation = 1e-10;
}  // namespace

void IkOptions::validate() const {
  require_non_negative("ik.damping", damping);
  require_non_negative("ik.position_gain", position_gain);
  require_non_negative("ik.orientation_gain", orientation_gain);
  require_non_negative("ik.posture_gain", posture_gain);
  require_in_range("ik.limit_margin", limit_margin, 0.0, 0.5);
  require_positive("ik.dt", dt);
  require_in_range("ik.velocity_scale", velocity_scale, 1e-6, 1.0);
}

void IkSolveOptions::validate() const {
  if (max_iterations < 1)
    throw InputError(fmt::format("ik.max_iterations: expected >= 1, got {}", max_iterations));
  require_positive("ik.position_tolerance", position_tolerance);
  require_positive("ik.orientation_tolerance", orientation_tolerance);
  step.validate();
}

Eigen::Matrix3d face_rotation(double heading) {
  return Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

Vector6 face_pose_error(const Eigen::Isometry3d& current, const Eigen::Vector3d& position,
                        const Eigen::Matrix3d& rotation) {
  Vector6 e;
  e.head<3>() = position - current.translation();
  e.tail<3>() = rotation_to_vector(rotation * current.linear().transpose());
  return e;
}

RtStatus velocity_ik(const ArmModel& arm, const Vector7& q, const Matrix67& jacobian,
                     const Vector6& task_velocity, const Vector7& posture_velocity,
                     const IkOptions& o, Vector7& qd) {
  if (!q.allFinite() || !jacobian.allFinite() || !task_velocity.allFinite() ||
      !posture_velocity.allFinite()) {
    qd.setZero();
    return RtStatus::kInvalidInput;
  }
  // Bounds for this period. Inside the margin band a joint may only move away from its limit.
  const Vector7 vmax = o.velocity_scale * arm.velocity_limit();
  const Vector7 room_lo = (arm.position_lower().array() + o.limit_margin - q.array()) / o.dt;
  const Vector7 room_hi = (arm.position_upper().array() - o.limit_margin - q.array()) / o.dt;
  const Vector7 lo = (-vmax).cwiseMax(room_lo.cwiseMin(0.0));
  const Vector7 hi = vmax.cwiseMin(room_hi.cwiseMax(0.0));

  RtStatus status = RtStatus::kOk;
  std::array<bool, kNumJoints> locked{};
  Vector7 fixed = Vector7::Zero();
  const Matrix6 damp = o.damping * o.damping * Matrix6::Identity();
  for (int pass = 0; pass <= kNumJoints; ++pass) {
    Matrix67 jf = jacobian;
    Vector7 z = posture_velocity;
    for (int i = 0; i < kNumJoints; ++i)
      if (locked[static_cast<std::size_t>(i)]) {
        jf.col(i).setZero();
        z(i) = 0.0;
      }
    const Matrix6 jjt = jf * jf.transpose();
    const Eigen::LLT<Matrix6> llt(jjt + damp);
    const Vector6 v = task_velocity - jacobian * fixed;
    // qd = J# v + (I - J+ J) z. The task uses the damped pseudo-inverse J# = J^T (J J^T + l^2
    // I)^-1; the null-space projector uses an almost undamped one, so the posture pull does not
    // leak into the task and bias it (its eigenvalues stay in [0, 1] whatever the conditioning).
    const Eigen::LLT<Matrix6> llt_null(jjt + kNullRegularisation * Matrix6::Identity());
    const Vector7 z_null = z - jf.transpose() * llt_null.solve(jf * z);
    qd = jf.transpose() * llt.solve(v) + z_null + fixed;

    // Lock the free joint with the worst bound violation and re-solve the task without it.
    int worst = -1;
    double worst_excess = 1e-12;
    for (int i = 0; i < kNumJoints; ++i) {
      if (locked[static_cast<std::size_t>(i)]) continue;
      const double excess = std::max(qd(i) - hi(i), lo(i) - qd(i));
      if (excess > worst_excess) {
        worst_excess = excess;
        worst = i;
      }
    }
    if (worst < 0) break;
    locked[static_cast<std::size_t>(worst)] = true;
    fixed(worst) = std::clamp(qd(worst), lo(worst), hi(worst));
    status = RtStatus::kSaturated;
  }
  qd = qd.cwiseMax(lo).cwiseMin(hi);
  return status;
}

RtStatus track_face(const ArmModel& arm, const Vector7& q, const FaceTarget& target,
                    const Vector7& posture, const IkOptions& o, Vector7& qd, Vector6* error) {
  if (!q.allFinite() || !target.position.allFinite() || !std::isfinite(target.heading) ||
      !target.velocity.allFinite() || !posture.allFinite()) {
    qd.setZero();
    if (error != nullptr) error->setZero();
    return RtStatus::kInvalidInput;
  }
  Eigen::Isometry3d pose;
  Matrix67 jacobian;
  dh_club_jacobian(arm, q, pose, jacobian);
  const Vector6 e = face_pose_error(pose, target.position, face_rotation(target.heading));
  if (error != nullptr) *error = e;
  Vector6 v = target.velocity;
  v.head<3>() += o.position_gain * e.head<3>();
  v.tail<3>() += o.orientation_gain * e.tail<3>();
  return velocity_ik(arm, q, jacobian, v, o.posture_gain * (posture - q), o, qd);
}

IkResult solve_ik(const ArmModel& arm, const FaceTarget& target, const Vector7& start,
                  const Vector7& posture, const IkSolveOptions& options) {
  options.validate();
  if (!start.allFinite() || !posture.allFinite() || !target.position.allFinite() ||
      !std::isfinite(target.heading))
    throw InputError("ik: expected finite start, posture and target");
  for (int i = 0; i < kNumJoints; ++i)
    if (start(i) < arm.position_lower()(i) || start(i) > arm.position_upper()(i))
      throw InputError(fmt::format("ik: start q[{}]: expected a value in [{}, {}], got {}", i,
                                   arm.position_lower()(i), arm.position_upper()(i), start(i)));
  FaceTarget static_target = target;
  static_target.velocity.setZero();
  const Vector7 clamped_posture =
      posture.cwiseMax(arm.position_lower()).cwiseMin(arm.position_upper());

  auto descend = [&](const Vector7& from, int budget) {
    IkResult r;
    r.q = from;
    Vector7 qd;
    Vector6 e;
    for (int it = 0; it < budget; ++it) {
      (void)track_face(arm, r.q, static_target, posture, options.step, qd, &e);
      r.iterations = it;
      r.position_error = e.head<3>().norm();
      r.orientation_error = e.tail<3>().norm();
      if (r.position_error < options.position_tolerance &&
          r.orientation_error < options.orientation_tolerance) {
        r.converged = true;
        return r;
      }
      r.q += options.step.dt * qd;
      r.q = r.q.cwiseMax(arm.position_lower()).cwiseMin(arm.position_upper());
    }
    r.iterations = budget;
    return r;
  };
  // A start far from the posture can stall against a joint limit; then restart once from the
  // posture with the remaining budget and keep the better outcome.
  const int first_budget =
      options.max_iterations / 2 > 0 ? options.max_iterations / 2 : options.max_iterations;
  IkResult first =
      descend(start, (start - clamped_posture).isZero() ? options.max_iterations : first_budget);
  if (first.converged || (start - clamped_posture).isZero() ||
      options.max_iterations - first.iterations < 1)
    return first;
  IkResult second = descend(clamped_posture, options.max_iterations - first.iterations);
  second.iterations += first.iterations;
  if (second.converged || second.position_error + second.orientation_error <
                              first.position_error + first.orientation_error)
    return second;
  first.iterations = second.iterations;
  return first;
}

}  // namespace mg::robot
