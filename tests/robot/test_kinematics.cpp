#include <fmt/format.h>
#include <gtest/gtest.h>

#include "robot/kinematics.hpp"
#include "robot_test_util.hpp"

namespace mg::robot {
namespace {

using testing::WamFixture;

double max_abs_diff(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff();
}

TEST(DhKinematics, ZeroPoseIsStraightUp) {
  const Eigen::Isometry3d t = dh_forward_kinematics(Vector7::Zero());
  // The 0.045 m elbow offsets cancel; the flange sits 0.55 + 0.30 + 0.0609 m above the shoulder.
  EXPECT_NEAR(t.translation().x(), 0.0, 1e-12);
  EXPECT_NEAR(t.translation().y(), 0.0, 1e-12);
  EXPECT_NEAR(t.translation().z(), 0.55 + 0.30 + 0.0609, 1e-12);
  EXPECT_NEAR(t.linear().col(2).z(), 1.0, 1e-12);
}

TEST(DhKinematics, LinkFramesChainToTheFlange) {
  Rng rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Vector7 q;
  for (int i = 0; i < kNumJoints; ++i) q(i) = u(rng);
  std::array<Eigen::Isometry3d, kNumJoints> frames;
  dh_link_frames(q, frames);
  EXPECT_LT(max_abs_diff(frames[6], dh_forward_kinematics(q)), 1e-15);
}

TEST_F(WamFixture, MujocoLinkFramesEqualDhForwardKinematics) {
  Rng rng(11);
  double worst = 0.0;
  std::array<Eigen::Isometry3d, kNumJoints> frames;
  for (int trial = 0; trial < 300; ++trial) {
    const Vector7 q = random_q(rng);
    pose_model(q);
    dh_link_frames(q, frames);
    for (int i = 0; i < kNumJoints; ++i) {
      const int b =
          mj_name2id(model_.get(), mjOBJ_BODY, ("wam_link" + std::to_string(i + 1)).c_str());
      Eigen::Isometry3d mj = Eigen::Isometry3d::Identity();
      mj.translation() = Eigen::Vector3d(data_->xpos + 3 * b);
      mj.linear() = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(data_->xmat + 9 * b);
      worst = std::max(
          worst, max_abs_diff(mj, arm_->shoulder_in_world() * frames[static_cast<std::size_t>(i)]));
    }
    worst = std::max(worst, max_abs_diff(club_pose(ids_, data_.get()), dh_club_pose(*arm_, q)));
    worst = std::max(worst, max_abs_diff(flange_pose(ids_, data_.get()), dh_flange_pose(*arm_, q)));
  }
  EXPECT_LT(worst, 1e-9);
  RecordProperty("max_fk_difference", fmt::format("{:.3g}", worst));
}

TEST_F(WamFixture, JacobianMatchesFiniteDifferencesAndDhJacobian) {
  Rng rng(12);
  const double h = 1e-6;
  for (int trial = 0; trial < 50; ++trial) {
    const Vector7 q = random_q(rng, 1e-3);
    pose_model(q);
    Matrix67 jac;
    club_jacobian(ids_, model_.get(), data_.get(), jac);
    Matrix67 fd;
    for (int i = 0; i < kNumJoints; ++i) {
      Vector7 qp = q, qm = q;
      qp(i) += h;
      qm(i) -= h;
      pose_model(qp);
      const Eigen::Isometry3d a = club_pose(ids_, data_.get());
      pose_model(qm);
      const Eigen::Isometry3d b = club_pose(ids_, data_.get());
      fd.block<3, 1>(0, i) = (a.translation() - b.translation()) / (2 * h);
      fd.block<3, 1>(3, i) = rotation_to_vector(a.linear() * b.linear().transpose()) / (2 * h);
    }
    EXPECT_LT((jac - fd).cwiseAbs().maxCoeff(), 1e-7) << "trial " << trial;
    Eigen::Isometry3d pose;
    Matrix67 dh_jac;
    dh_club_jacobian(*arm_, q, pose, dh_jac);
    EXPECT_LT((jac - dh_jac).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
  }
}

TEST(DhKinematics, RotationVectorRoundTrips) {
  Rng rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    Eigen::Vector3d w(n(rng), n(rng), n(rng));
    if (w.norm() > 3.0) w *= 3.0 / w.norm();
    EXPECT_LT((rotation_to_vector(rotation_from_vector(w)) - w).norm(), 1e-12);
  }
  EXPECT_LT(rotation_to_vector(Eigen::Matrix3d::Identity()).norm(), 1e-15);
}

}  // namespace
}  // namespace mg::robot
