#pragma once
// Shared fixture: the standalone WAM model compiled once per test, its ArmModel, its MuJoCo ids
// and random joint configurations inside the limits.
#include <gtest/gtest.h>

#include <random>

#include "core/rng.hpp"
#include "robot/arm_model.hpp"
#include "sim_backend/arm_mujoco.hpp"
#include "sim_backend/wam_mjcf.hpp"

namespace mg::robot::testing {

// Fails the test on any MuJoCo warning raised while the fixture's data is in use.
inline void expect_no_warnings(const mjData* d) {
  for (int i = 0; i < mjNWARNING; ++i) EXPECT_EQ(d->warning[i].number, 0) << "MuJoCo warning " << i;
}

class WamFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    model_ = compile_mjcf(wam_standalone_mjcf(mount_));
    data_.reset(mj_makeData(model_.get()));
    arm_ = std::make_unique<ArmModel>(arm_model_from_mujoco(model_.get(), mount_));
    ids_ = find_arm_ids(model_.get());
  }
  void TearDown() override { expect_no_warnings(data_.get()); }

  // Uniform inside the limits shrunk by `inset` [rad].
  Vector7 random_q(Rng& rng, double inset = 0.0) const {
    Vector7 q;
    for (int i = 0; i < kNumJoints; ++i) {
      std::uniform_real_distribution<double> u(arm_->position_lower()(i) + inset,
                                               arm_->position_upper()(i) - inset);
      q(i) = u(rng);
    }
    return q;
  }
  static Vector7 random_vector(Rng& rng, double scale) {
    std::uniform_real_distribution<double> u(-scale, scale);
    Vector7 v;
    for (int i = 0; i < kNumJoints; ++i) v(i) = u(rng);
    return v;
  }
  // Sets q, runs kinematics and the COM positions (what mj_jacSite needs).
  void pose_model(const Vector7& q) {
    set_joint_positions(ids_, data_.get(), q);
    mj_kinematics(model_.get(), data_.get());
    mj_comPos(model_.get(), data_.get());
  }

  WamMount mount_{};
  sim::ModelPtr model_;
  sim::DataPtr data_;
  std::unique_ptr<ArmModel> arm_;
  ArmIds ids_;  ///< the arm in model_
};

inline Vector7 rest_posture() { return Vector7(kDefaultRestPosture.data()); }

}  // namespace mg::robot::testing
