#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "robot/ik.hpp"
#include "robot_test_util.hpp"

namespace mg::robot {
namespace {

using testing::rest_posture;
using testing::WamFixture;

constexpr double kDeg = kPi / 180.0;

// Face orientation error measured on the MuJoCo model: angle between the face normal and the
// hitting direction, and how far the face is from vertical.
struct FaceCheck {
  double position_error;
  double normal_error;
  double tilt;
};

class WamIk : public WamFixture {
 protected:
  FaceCheck check_with_mujoco(const Vector7& q, const FaceTarget& t) {
    pose_model(q);
    const Eigen::Isometry3d face = club_pose(ids_, data_.get());
    const Eigen::Vector3d normal = face.linear().col(0);
    const Eigen::Vector3d wanted(std::cos(t.heading), std::sin(t.heading), 0.0);
    return {(face.translation() - t.position).norm(),
            std::acos(std::clamp(normal.dot(wanted), -1.0, 1.0)),
            std::acos(std::clamp(face.linear()(2, 2), -1.0, 1.0))};
  }
  bool within_limits(const Vector7& q) const {
    return (q.array() >= arm_->position_lower().array()).all() &&
           (q.array() <= arm_->position_upper().array()).all();
  }
};

// The default mount must reach the whole hitting region with a vertical face turned +-0.5 rad.
TEST_F(WamIk, ReachesTheHittingRegionWithinOneMillimetreAndOneDegree) {
  int targets = 0;
  double worst_margin = 1e9, worst_pos = 0.0, worst_ang = 0.0;
  for (double x : {-0.45, -0.3, -0.15, 0.0, 0.1})
    for (double y : {-0.15, 0.0, 0.15})
      for (double z : {0.02, 0.16, 0.30})
        for (double heading : {-0.5, 0.0, 0.5}) {
          FaceTarget t;
          t.position = {x, y, z};
          t.heading = heading;
          const IkResult r = solve_ik(*arm_, t, rest_posture(), rest_posture());
          ++targets;
          EXPECT_TRUE(r.converged) << x << " " << y << " " << z << " " << heading;
          EXPECT_TRUE(within_limits(r.q));
          const FaceCheck c = check_with_mujoco(r.q, t);
          EXPECT_LT(c.position_error, 1e-3);
          EXPECT_LT(c.normal_error, 1.0 * kDeg);
          EXPECT_LT(c.tilt, 1.0 * kDeg);
          worst_pos = std::max(worst_pos, c.position_error);
          worst_ang = std::max({worst_ang, c.normal_error, c.tilt});
          const Vector7 room =
              (r.q - arm_->position_lower()).cwiseMin(arm_->position_upper() - r.q);
          worst_margin = std::min(worst_margin, room.minCoeff());
        }
  EXPECT_EQ(targets, 135);
  // Solutions stay clear of the limits (the IK keeps a 0.05 rad margin; the mount gives more).
  EXPECT_GT(worst_margin, 0.1);
  RecordProperty("worst_position_error_m", fmt::format("{:.3g}", worst_pos));
  RecordProperty("worst_angle_error_rad", fmt::format("{:.3g}", worst_ang));
  RecordProperty("worst_joint_margin_rad", fmt::format("{:.3g}", worst_margin));
}

// Random targets in the region, each IK started from the previous solution (as the controller
// would): all converge, within limits.
TEST_F(WamIk, ReachesRandomTargetsFromChainedStarts) {
  Rng rng(41);
  std::uniform_real_distribution<double> ux(-0.45, 0.1), uy(-0.15, 0.15), uz(0.02, 0.30),
      uh(-0.5, 0.5);
  Vector7 q = rest_posture();
  int failures = 0;
  for (int k = 0; k < 300; ++k) {
    FaceTarget t;
    t.position = {ux(rng), uy(rng), uz(rng)};
    t.heading = uh(rng);
    const IkResult r = solve_ik(*arm_, t, q, rest_posture());
    if (!r.converged) {
      ++failures;
      continue;
    }
    EXPECT_TRUE(within_limits(r.q));
    EXPECT_LT(check_with_mujoco(r.q, t).position_error, 1e-3);
    q = r.q;
  }
  EXPECT_EQ(failures, 0);
}

TEST_F(WamIk, RestPostureHoldsTheFaceVerticalAtTheRegionCentre) {
  FaceTarget t;
  t.position = {-0.175, 0.0, 0.16};
  const FaceCheck c = check_with_mujoco(rest_posture(), t);
  EXPECT_LT(c.position_error, 1e-3);
  EXPECT_LT(c.normal_error, 0.1 * kDeg);
  EXPECT_LT(c.tilt, 0.1 * kDeg);
}

TEST_F(WamIk, VelocityIkReproducesAFeasibleTaskVelocity) {
  Rng rng(31);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  const IkOptions options;
  Eigen::Isometry3d pose;
  Matrix67 jac;
  dh_club_jacobian(*arm_, rest_posture(), pose, jac);
  // Damped least squares leaves a residual of at most lambda^2 / (sigma_min^2 + lambda^2) of |v|.
  const Vector6 sigma = Eigen::JacobiSVD<Matrix67>(jac).singularValues();
  const double l2 = options.damping * options.damping;
  const double bound = l2 / (sigma(5) * sigma(5) + l2);
  ASSERT_LT(bound, 0.05);  // the rest posture is well conditioned
  for (int trial = 0; trial < 20; ++trial) {
    Vector6 v;
    for (int i = 0; i < 6; ++i) v(i) = u(rng);
    Vector7 qd;
    ASSERT_EQ(velocity_ik(*arm_, rest_posture(), jac, v, Vector7::Zero(), options, qd),
              RtStatus::kOk);
    EXPECT_LE((jac * qd - v).norm() / v.norm(), bound * (1.0 + 1e-9));
  }
  // Without damping the task velocity is reproduced exactly.
  IkOptions undamped = options;
  undamped.damping = 0.0;
  Vector6 v;
  v << 0.1, -0.2, 0.05, 0.3, -0.1, 0.2;
  Vector7 exact;
  ASSERT_EQ(velocity_ik(*arm_, rest_posture(), jac, v, Vector7::Zero(), undamped, exact),
            RtStatus::kOk);
  EXPECT_LT((jac * exact - v).norm(), 1e-10);
  // A pure posture velocity lives in the null space: the face does not move.
  Vector7 qd;
  const Vector7 z = 0.3 * Vector7::Ones();
  ASSERT_EQ(velocity_ik(*arm_, rest_posture(), jac, Vector6::Zero(), z, options, qd),
            RtStatus::kOk);
  EXPECT_LT((jac * qd).norm(), 1e-6);
  EXPECT_GT(qd.norm(), 1e-3);
}

// Closed loop at 500 Hz: the face follows a target gliding along the hitting direction.
TEST_F(WamIk, TrackFaceFollowsAMovingTarget) {
  const IkOptions options;
  Vector7 q = rest_posture();
  FaceTarget t;
  t.heading = 0.3;
  const Eigen::Vector3d start(-0.30, -0.05, 0.05);
  t.position = start;
  ASSERT_TRUE(solve_ik(*arm_, t, q, rest_posture()).converged);
  q = solve_ik(*arm_, t, q, rest_posture()).q;
  const double speed = 0.5;  // [m/s]
  const Eigen::Vector3d dir(std::cos(t.heading), std::sin(t.heading), 0.0);
  double worst = 0.0;
  Vector7 qd;
  Vector6 e;
  for (int k = 0; k < 300; ++k) {  // 0.6 s, 0.3 m
    const double time = k * options.dt;
    t.position = start + speed * time * dir;
    t.velocity.head<3>() = speed * dir;
    const RtStatus s = track_face(*arm_, q, t, rest_posture(), options, qd, &e);
    ASSERT_NE(s, RtStatus::kInvalidInput);
    worst = std::max(worst, e.head<3>().norm());
    q += options.dt * qd;
    ASSERT_TRUE(within_limits(q));
  }
  EXPECT_LT(worst, 2e-3);
  const FaceCheck c = check_with_mujoco(q, t);
  EXPECT_LT(c.position_error, 2e-3);
  EXPECT_LT(c.normal_error, 1.0 * kDeg);
  RecordProperty("worst_tracking_error_m", fmt::format("{:.3g}", worst));
}

// Random states and wild task velocities: the output never leaves the velocity bounds and never
// carries a joint past its position limit less the margin.
TEST_F(WamIk, VelocityIkRespectsJointBounds) {
  Rng rng(32);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const IkOptions options;
  int saturated = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Vector7 q = random_q(rng, options.limit_margin);
    Eigen::Isometry3d pose;
    Matrix67 jac;
    dh_club_jacobian(*arm_, q, pose, jac);
    Vector6 v;
    for (int i = 0; i < 6; ++i) v(i) = u(rng);
    Vector7 qd;
    const RtStatus s = velocity_ik(*arm_, q, jac, v, random_vector(rng, 1.0), options, qd);
    ASSERT_NE(s, RtStatus::kInvalidInput);
    if (s == RtStatus::kSaturated) ++saturated;
    for (int i = 0; i < kNumJoints; ++i) {
      EXPECT_LE(std::abs(qd(i)), arm_->velocity_limit()(i) + 1e-12);
      const double next = q(i) + options.dt * qd(i);
      EXPECT_GE(next, arm_->position_lower()(i) + options.limit_margin - 1e-12);
      EXPECT_LE(next, arm_->position_upper()(i) - options.limit_margin + 1e-12);
    }
  }
  EXPECT_GT(saturated, 0);  // the bounds were actually exercised
}

// The joint velocity limits are sized for a putt (notes/robot.md): at the impact posture of
// hitting angles 0..0.6 rad the IK produces a 2.5 m/s face velocity along the hitting direction,
// heading held, without a joint reaching its velocity bound (the old 2-3 rad/s limits could not).
TEST_F(WamIk, VelocityLimitsAdmitAPuttAtTwoAndAHalfMetresPerSecond) {
  const IkOptions options;
  for (double theta : {0.0, 0.3, 0.6}) {
    const Eigen::Vector3d psi(std::cos(theta), std::sin(theta), 0.0);
    FaceTarget t;
    t.position = Eigen::Vector3d(0.0, 0.0, 0.02135) - 0.021335 * psi;  // face touching the ball
    t.heading = theta;
    const IkResult r = solve_ik(*arm_, t, rest_posture(), rest_posture());
    ASSERT_TRUE(r.converged) << theta;
    Eigen::Isometry3d pose;
    Matrix67 jac;
    dh_club_jacobian(*arm_, r.q, pose, jac);
    Vector6 v = Vector6::Zero();
    v.head<3>() = 2.5 * psi;
    Vector7 qd;
    EXPECT_EQ(velocity_ik(*arm_, r.q, jac, v, Vector7::Zero(), options, qd), RtStatus::kOk)
        << theta;
    EXPECT_LT((jac * qd - v).norm() / v.norm(), 0.01) << theta;
    EXPECT_LT(qd.cwiseAbs().cwiseQuotient(arm_->velocity_limit()).maxCoeff(), 0.9) << theta;
  }
}

// At a limit the IK still does the best it can with the other joints.
TEST_F(WamIk, ALockedJointIsTakenOutOfTheTask) {
  Vector7 q = rest_posture();
  Eigen::Isometry3d pose;
  Matrix67 jac;
  dh_club_jacobian(*arm_, q, pose, jac);
  IkOptions options;
  Vector6 v = Vector6::Zero();
  v(0) = 0.2;
  Vector7 free_qd;
  ASSERT_EQ(velocity_ik(*arm_, q, jac, v, Vector7::Zero(), options, free_qd), RtStatus::kOk);
  // Tell the IK that the joint that moves most sits at its limit, on the side it wants to move to
  // (same Jacobian: only the bounds change).
  int j = 0;
  free_qd.cwiseAbs().maxCoeff(&j);
  q(j) = free_qd(j) > 0 ? arm_->position_upper()(j) - options.limit_margin
                        : arm_->position_lower()(j) + options.limit_margin;
  Vector7 qd;
  EXPECT_EQ(velocity_ik(*arm_, q, jac, v, Vector7::Zero(), options, qd), RtStatus::kSaturated);
  EXPECT_NEAR(qd(j), 0.0, 1e-12);
  // The other six joints still span the 6-D task, so the task is still met up to the DLS bias.
  Matrix67 reduced = jac;
  reduced.col(j).setZero();
  ASSERT_GT(Eigen::JacobiSVD<Matrix67>(reduced).singularValues()(5), 0.05);
  EXPECT_LT((jac * qd - v).norm() / v.norm(), 0.1);
  EXPECT_GT((qd - free_qd).norm(), 1e-3);  // the others moved differently to compensate
}

TEST_F(WamIk, BadInputGivesStatusInRealTimeAndThrowsInTheSolver) {
  const IkOptions options;
  Vector7 q = rest_posture();
  q(2) = std::numeric_limits<double>::quiet_NaN();
  Matrix67 jac = Matrix67::Zero();
  Vector7 qd = Vector7::Ones();
  EXPECT_EQ(velocity_ik(*arm_, q, jac, Vector6::Zero(), Vector7::Zero(), options, qd),
            RtStatus::kInvalidInput);
  EXPECT_TRUE(qd.isZero());
  FaceTarget t;
  qd.setOnes();
  Vector6 e = Vector6::Ones();
  EXPECT_EQ(track_face(*arm_, q, t, rest_posture(), options, qd, &e), RtStatus::kInvalidInput);
  EXPECT_TRUE(qd.isZero());
  EXPECT_TRUE(e.isZero());
  EXPECT_THROW((void)solve_ik(*arm_, t, q, rest_posture()), InputError);
  Vector7 outside = rest_posture();
  outside(1) = 5.0;
  EXPECT_THROW((void)solve_ik(*arm_, t, outside, rest_posture()), InputError);
  IkSolveOptions bad;
  bad.step.dt = 0.0;
  EXPECT_THROW((void)solve_ik(*arm_, t, rest_posture(), rest_posture(), bad), InputError);
}

// A target far out of reach does not converge but returns a finite, in-limits posture.
TEST_F(WamIk, UnreachableTargetReportsNoConvergence) {
  FaceTarget t;
  t.position = {3.0, 0.0, 0.1};
  IkSolveOptions options;
  options.max_iterations = 300;
  const IkResult r = solve_ik(*arm_, t, rest_posture(), rest_posture(), options);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.q.allFinite());
  EXPECT_TRUE(within_limits(r.q));
  EXPECT_GT(r.position_error, 1.0);
}

}  // namespace
}  // namespace mg::robot
