// The WAM as MJCF (sim_backend/wam_mjcf.hpp) and read back from a compiled model
// (sim_backend/arm_mujoco.hpp): its tables, contacts and ids.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "robot/kinematics.hpp"
#include "robot_test_util.hpp"

namespace mg::robot {
namespace {

using testing::WamFixture;

Eigen::Matrix3d tensor(const LinkInertial& l) {
  const auto& i = l.inertia;
  Eigen::Matrix3d t;
  t << i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2];
  return t;
}

// Inertia tensor of body b about its COM in the body frame, from MuJoCo's principal form.
Eigen::Matrix3d compiled_inertia_of(const mjModel* m, int b) {
  double mat[9];
  mju_quat2Mat(mat, m->body_iquat + 4 * b);
  const Eigen::Matrix3d r = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(mat);
  return r * Eigen::Vector3d(m->body_inertia + 3 * b).asDiagonal() * r.transpose();
}

TEST_F(WamFixture, CompilesWithSevenJointsAndActuators) {
  EXPECT_EQ(model_->nq, kNumJoints);
  EXPECT_EQ(model_->nv, kNumJoints);
  EXPECT_EQ(model_->nu, kNumJoints);
  EXPECT_GE(ids_.site, 0);
  EXPECT_GE(ids_.flange_body, 0);
}

TEST_F(WamFixture, JointRangesArmatureDampingEqualTables) {
  for (int i = 0; i < kNumJoints; ++i) {
    const int j = mj_name2id(model_.get(), mjOBJ_JOINT, ("wam_j" + std::to_string(i + 1)).c_str());
    ASSERT_GE(j, 0);
    const auto k = static_cast<std::size_t>(i);
    EXPECT_TRUE(model_->jnt_limited[j]);
    EXPECT_DOUBLE_EQ(model_->jnt_range[2 * j], kJointLower[k]);
    EXPECT_DOUBLE_EQ(model_->jnt_range[2 * j + 1], kJointUpper[k]);
    EXPECT_DOUBLE_EQ(model_->dof_armature[model_->jnt_dofadr[j]], kArmature[k]);
    EXPECT_DOUBLE_EQ(model_->dof_damping[model_->jnt_dofadr[j]], kDamping[k]);
  }
}

TEST_F(WamFixture, TorqueActuatorsEqualTorqueLimits) {
  for (int i = 0; i < kNumJoints; ++i) {
    const int a =
        mj_name2id(model_.get(), mjOBJ_ACTUATOR, ("wam_m" + std::to_string(i + 1)).c_str());
    ASSERT_GE(a, 0);
    const auto k = static_cast<std::size_t>(i);
    EXPECT_TRUE(model_->actuator_ctrllimited[a]);
    EXPECT_DOUBLE_EQ(model_->actuator_ctrlrange[2 * a], -kTorqueLimit[k]);
    EXPECT_DOUBLE_EQ(model_->actuator_ctrlrange[2 * a + 1], kTorqueLimit[k]);
    EXPECT_DOUBLE_EQ(model_->actuator_gear[6 * a], 1.0);
    EXPECT_EQ(model_->actuator_trnid[2 * a],
              mj_name2id(model_.get(), mjOBJ_JOINT, ("wam_j" + std::to_string(i + 1)).c_str()));
  }
}

TEST_F(WamFixture, LinkMassesAndCentresEqualTables) {
  for (int i = 0; i < kNumJoints; ++i) {
    const int b =
        mj_name2id(model_.get(), mjOBJ_BODY, ("wam_link" + std::to_string(i + 1)).c_str());
    ASSERT_GE(b, 0);
    const auto& l = kLinkInertials[static_cast<std::size_t>(i)];
    EXPECT_NEAR(model_->body_mass[b], l.mass, 1e-12);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(model_->body_ipos[3 * b + c], l.com[static_cast<std::size_t>(c)], 1e-12);
    // The compiled principal moments and axes give back the tabulated tensor in the DH frame.
    EXPECT_LT((compiled_inertia_of(model_.get(), b) - tensor(l)).cwiseAbs().maxCoeff(), 1e-15)
        << "link " << i + 1;
  }
  const int club = mj_name2id(model_.get(), mjOBJ_BODY, "wam_club");
  ASSERT_GE(club, 0);
  const LinkInertial c = club_inertial(mount_.club);
  EXPECT_NEAR(model_->body_mass[club], mount_.club.shaft_mass + mount_.club.head_mass, 1e-12);
  EXPECT_LT((compiled_inertia_of(model_.get(), club) - tensor(c)).cwiseAbs().maxCoeff(), 1e-15);
  // The club body frame is the flange frame.
  EXPECT_EQ(model_->body_parentid[club], mj_name2id(model_.get(), mjOBJ_BODY, "wam_link7"));
  for (int k = 0; k < 3; ++k) EXPECT_EQ(model_->body_pos[3 * club + k], 0.0);
}

TEST_F(WamFixture, OnlyTheClubHeadCollidesAndOnlyWithBitFour) {
  const int head = mj_name2id(model_.get(), mjOBJ_GEOM, "club_head");
  ASSERT_GE(head, 0);
  EXPECT_EQ(model_->geom_contype[head], 4);
  EXPECT_EQ(model_->geom_conaffinity[head], 0);
  for (int g = 0; g < model_->ngeom; ++g) {
    if (g == head) continue;
    EXPECT_EQ(model_->geom_contype[g], 0) << "geom " << g;
    EXPECT_EQ(model_->geom_conaffinity[g], 0) << "geom " << g;
  }
}

// The inserted arm works inside a larger world; the ball (conaffinity 4) touches the club head.
TEST(WamModel, BodiesInsertIntoAWorldAndTheHeadHitsABall) {
  const WamMount mount;
  const ArmModel dh_arm(mount);
  const Eigen::Isometry3d face = dh_club_pose(dh_arm, Vector7(kDefaultRestPosture.data()));
  // A ball 1 cm in front of the face, moving against it.
  const Eigen::Vector3d ball = face.translation() + (0.0213 + 0.01) * face.linear().col(0);
  const std::string xml =
      fmt::format(R"(<mujoco><compiler angle="radian"/><option timestep="0.001"/>
<worldbody><geom name="lane" type="plane" size="3 3 0.1" contype="1" conaffinity="0"/>
<body name="ball" pos="{} {} {}"><freejoint/><geom name="ball" type="sphere" size="0.0213" mass="0.046" contype="0" conaffinity="5"/></body>
{}</worldbody><actuator>{}</actuator></mujoco>)",
                  ball.x(), ball.y(), ball.z(), wam_bodies_mjcf(mount), wam_actuators_mjcf());
  sim::ModelPtr m = compile_mjcf(xml);
  sim::DataPtr d(mj_makeData(m.get()));
  set_joint_positions(find_arm_ids(m.get()), d.get(), Vector7(kDefaultRestPosture.data()));
  const int ball_body = mj_name2id(m.get(), mjOBJ_BODY, "ball");
  const int ball_dof = m->jnt_dofadr[m->body_jntadr[ball_body]];
  for (int c = 0; c < 3; ++c) d->qvel[ball_dof + c] = -0.5 * face.linear()(c, 0);
  const int head = mj_name2id(m.get(), mjOBJ_GEOM, "club_head");
  bool touched = false;
  for (int step = 0; step < 100 && !touched; ++step) {
    mj_step(m.get(), d.get());
    for (int c = 0; c < d->ncon; ++c) {
      const int g1 = d->contact[c].geom1, g2 = d->contact[c].geom2;
      if (g1 == head || g2 == head) touched = true;
      // The head never touches the lane plane; the arm never touches anything.
      EXPECT_TRUE(m->geom_bodyid[g1] == ball_body || m->geom_bodyid[g2] == ball_body);
    }
  }
  EXPECT_TRUE(touched);
  testing::expect_no_warnings(d.get());
}

TEST(WamModel, BadInputIsRejectedWithANamedError) {
  WamMount mount;
  mount.base_yaw = std::nan("");
  EXPECT_THROW((void)wam_bodies_mjcf(mount), InputError);
  EXPECT_THROW((void)compile_mjcf("<mujoco><worldbody><body></mujoco>"), Error);
  // A model compiled for one mount does not pass for another.
  sim::ModelPtr m = compile_mjcf(wam_standalone_mjcf(WamMount{}));
  WamMount other;
  other.base_position[0] += 0.1;
  EXPECT_THROW((void)arm_model_from_mujoco(m.get(), other), InputError);
  EXPECT_THROW((void)arm_model_from_mujoco(nullptr, other), InputError);
  EXPECT_THROW((void)find_arm_ids(nullptr), InputError);
}

}  // namespace
}  // namespace mg::robot
