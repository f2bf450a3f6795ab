#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "robot/dynamics.hpp"
#include "robot_test_util.hpp"

namespace mg::robot {
namespace {

class WamDynamics : public testing::WamFixture {
 protected:
  void SetUp() override {
    WamFixture::SetUp();
    // mj_inverse with the Euler integrator and joint damping solves for the implicit-damping
    // acceleration; RK4 makes qfrc_inverse the plain continuous-time M qdd + c + g - passive.
    // No constraint forces either (random q stay inside the limits anyway).
    model_->opt.integrator = mjINT_RK4;
    model_->opt.disableflags |= mjDSBL_CONSTRAINT;
  }
};

TEST_F(WamDynamics, RneaEqualsMujocoInverseDynamics) {
  Rng rng(21);
  double worst_rel = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vector7 q = random_q(rng), qd = random_vector(rng, 2.0), qdd = random_vector(rng, 10.0);
    set_joint_positions(ids_, data_.get(), q);
    for (int i = 0; i < kNumJoints; ++i) {
      data_->qvel[ids_.dof[static_cast<std::size_t>(i)]] = qd(i);
      data_->qacc[ids_.dof[static_cast<std::size_t>(i)]] = qdd(i);
    }
    mj_inverse(model_.get(), data_.get());
    Vector7 tau;
    ASSERT_EQ(inverse_dynamics(*arm_, q, qd, qdd, tau), RtStatus::kOk);
    for (int i = 0; i < kNumJoints; ++i) {
      const double mj = data_->qfrc_inverse[ids_.dof[static_cast<std::size_t>(i)]];
      const double rel = std::abs(tau(i) - mj) / std::max(1.0, std::abs(mj));
      worst_rel = std::max(worst_rel, rel);
    }
  }
  EXPECT_LT(worst_rel, 1e-8);
  RecordProperty("max_relative_id_difference", fmt::format("{:.3g}", worst_rel));
}

TEST_F(WamDynamics, GravityTorqueEqualsMujocoBiasAtRest) {
  Rng rng(22);
  for (int trial = 0; trial < 50; ++trial) {
    const Vector7 q = random_q(rng);
    set_joint_positions(ids_, data_.get(), q);
    mj_forward(model_.get(), data_.get());
    Vector7 g;
    ASSERT_EQ(gravity_torque(*arm_, q, g), RtStatus::kOk);
    for (int i = 0; i < kNumJoints; ++i)
      EXPECT_NEAR(g(i), data_->qfrc_bias[ids_.dof[static_cast<std::size_t>(i)]], 1e-9);
  }
}

TEST_F(WamDynamics, MassMatrixIsSymmetricPositiveDefiniteAndEqualsMujoco) {
  Rng rng(23);
  std::vector<double> full(static_cast<std::size_t>(model_->nv * model_->nv));
  for (int trial = 0; trial < 50; ++trial) {
    const Vector7 q = random_q(rng);
    Matrix7 mass;
    ASSERT_EQ(mass_matrix(*arm_, q, mass), RtStatus::kOk);
    EXPECT_LT((mass - mass.transpose()).cwiseAbs().maxCoeff(), 1e-12);
    const Eigen::SelfAdjointEigenSolver<Matrix7> eig(mass);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
    // Without armature the rigid-body M alone must still be positive definite.
    Matrix7 rigid;
    ASSERT_EQ(mass_matrix(*arm_, q, rigid, false), RtStatus::kOk);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix7>(rigid).eigenvalues().minCoeff(), 0.0);

    set_joint_positions(ids_, data_.get(), q);
    mj_forward(model_.get(), data_.get());
    mj_fullM(model_.get(), full.data(), data_->qM);
    for (int r = 0; r < kNumJoints; ++r)
      for (int c = 0; c < kNumJoints; ++c)
        EXPECT_NEAR(
            mass(r, c),
            full[static_cast<std::size_t>(ids_.dof[static_cast<std::size_t>(r)] * model_->nv +
                                          ids_.dof[static_cast<std::size_t>(c)])],
            1e-10);
  }
}

TEST_F(WamDynamics, ArmatureAndDampingTermsAreSeparable) {
  Rng rng(24);
  const Vector7 q = random_q(rng), qd = random_vector(rng, 1.0), qdd = random_vector(rng, 5.0);
  Vector7 full, bare;
  ASSERT_EQ(inverse_dynamics(*arm_, q, qd, qdd, full), RtStatus::kOk);
  ASSERT_EQ(inverse_dynamics(*arm_, q, qd, qdd, bare, {false, false, true}), RtStatus::kOk);
  const Vector7 expected = arm_->armature().cwiseProduct(qdd) + arm_->damping().cwiseProduct(qd);
  EXPECT_LT((full - bare - expected).cwiseAbs().maxCoeff(), 1e-12);
  // Gravity off at rest gives zero torque.
  Vector7 none;
  ASSERT_EQ(inverse_dynamics(*arm_, q, Vector7::Zero(), Vector7::Zero(), none, {true, true, false}),
            RtStatus::kOk);
  EXPECT_LT(none.cwiseAbs().maxCoeff(), 1e-15);
}

TEST_F(WamDynamics, HoldingTheRestPostureNeedsLessThanTheTorqueLimits) {
  Vector7 g;
  ASSERT_EQ(gravity_torque(*arm_, testing::rest_posture(), g), RtStatus::kOk);
  for (int i = 0; i < kNumJoints; ++i)
    EXPECT_LT(std::abs(g(i)), 0.8 * arm_->torque_limit()(i)) << "joint " << i;
}

// Computed-torque control with our RNEA holds the rest posture in the MuJoCo simulation (Euler,
// 1 ms) within the torque limits: the model, its armature and the dynamics agree in closed loop.
TEST(WamSimulation, ComputedTorqueHoldsAndMovesTheArm) {
  const WamMount mount;
  sim::ModelPtr m = compile_mjcf(wam_standalone_mjcf(mount));
  sim::DataPtr d(mj_makeData(m.get()));
  const ArmModel arm = arm_model_from_mujoco(m.get(), mount);
  const ArmIds ids = find_arm_ids(m.get());
  const Vector7 rest = testing::rest_posture();
  set_joint_positions(ids, d.get(), rest);
  const double kp = 400.0, kd = 40.0;  // [1/s^2], [1/s]
  double worst = 0.0, peak_ratio = 0.0;
  for (int step = 0; step < 2000; ++step) {
    const double t = step * m->opt.timestep;
    // After 0.5 s of holding still, J1, J2 and J4 swing 0.2 rad out and back at 1 Hz (starting at
    // zero velocity).
    Vector7 qd_ref = Vector7::Zero(), q_ref = rest, qdd_ref = Vector7::Zero();
    if (t > 0.5) {
      const double w = 2.0 * kPi, s = w * (t - 0.5);
      for (int j : {0, 1, 3}) {
        q_ref(j) += 0.1 * (1.0 - std::cos(s));
        qd_ref(j) = 0.1 * w * std::sin(s);
        qdd_ref(j) = 0.1 * w * w * std::cos(s);
      }
    }
    const Vector7 q = joint_positions(ids, d.get()), qd = joint_velocities(ids, d.get());
    const Vector7 acc = qdd_ref + kp * (q_ref - q) + kd * (qd_ref - qd);
    Vector7 tau;
    ASSERT_EQ(inverse_dynamics(arm, q, qd, acc, tau), RtStatus::kOk);
    for (int i = 0; i < kNumJoints; ++i) {
      d->ctrl[ids.actuator[static_cast<std::size_t>(i)]] = tau(i);
      peak_ratio = std::max(peak_ratio, std::abs(tau(i)) / arm.torque_limit()(i));
    }
    mj_step(m.get(), d.get());
    worst = std::max(worst, (joint_positions(ids, d.get()) - q_ref).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 2e-3);
  EXPECT_LT(peak_ratio, 1.0);
  testing::expect_no_warnings(d.get());
  RecordProperty("worst_tracking_error_rad", fmt::format("{:.3g}", worst));
}

TEST_F(WamDynamics, NonFiniteInputGivesAStatusNotAThrow) {
  Vector7 q = testing::rest_posture();
  q(3) = std::numeric_limits<double>::quiet_NaN();
  Vector7 tau = Vector7::Constant(7.0);
  EXPECT_EQ(inverse_dynamics(*arm_, q, Vector7::Zero(), Vector7::Zero(), tau),
            RtStatus::kInvalidInput);
  EXPECT_TRUE(tau.isZero());
  Vector7 qd = Vector7::Zero();
  qd(0) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(inverse_dynamics(*arm_, testing::rest_posture(), qd, Vector7::Zero(), tau),
            RtStatus::kInvalidInput);
  EXPECT_EQ(gravity_torque(*arm_, q, tau), RtStatus::kInvalidInput);
  Matrix7 mass;
  EXPECT_EQ(mass_matrix(*arm_, q, mass), RtStatus::kInvalidInput);
  EXPECT_TRUE(mass.isZero());
}

}  // namespace
}  // namespace mg::robot
