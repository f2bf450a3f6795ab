// The stages of the core update one by one, with no simulator (the arm's published model, a
// perception written by hand): observe, transition, reference, track, hold, torque.
#include "control/module_stages.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "ds/hitting_model.hpp"
#include "robot/dynamics.hpp"
#include "robot/wam_model.hpp"

namespace mg::control {
namespace {

constexpr double kBallRadius = 0.021335;

robot::Vector7 rest_posture() {
  robot::Vector7 q;
  for (int j = 0; j < 7; ++j) q[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  return q;
}

struct Stages {
  ModuleModel model{robot::ArmModel(robot::WamMount{}),
                    ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                           "/data/models/hitting-default.json"),
                    ControllerConfig{}, kBallRadius};
  ModuleData data{model};
  MeasuredState measured;

  Stages() {
    measured.q = rest_posture();
    module_reset(model, data, measured.q);
  }
  /// A fresh perception with the ball at the hitting point.
  perception::Perceived ball_in_place() const {
    perception::Perceived p;
    p.fresh = true;
    p.age = 0.0;
    const Eigen::Vector3d& x = model.hitting().x_star();
    p.ball = {x.x(), x.y(), x.z()};
    p.hole = {2.0, 0.0, 0.0};
    return p;
  }
};

TEST(ModuleStages, ObserveConsumesTheCommandAndTakesThePerception) {
  Stages s;
  ASSERT_TRUE(request_rest(s.model, s.data, 0.0));
  s.measured.perception = s.ball_in_place();
  const Observation obs = observe(s.model, s.data, s.measured);
  EXPECT_EQ(obs.command, Command::kRest);
  EXPECT_EQ(s.data.pending, Command::kNone);  // consumed
  EXPECT_TRUE(obs.perception_fresh);
  EXPECT_TRUE(obs.ball_in_place);
  EXPECT_FALSE(obs.fault);
}

TEST(ModuleStages, ObserveFindsAFaultInABrokenOrOutOfRangeMeasurement) {
  Stages s;
  s.measured.q[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(observe(s.model, s.data, s.measured).fault);
  Stages t;
  t.measured.q[0] = t.model.arm().position_upper()[0] + 0.1;  // [rad] past the joint's end
  EXPECT_TRUE(observe(t.model, t.data, t.measured).fault);
}

TEST(ModuleStages, TransitionEntersRestAndIdleFollowsTheMeasurement) {
  Stages s;
  Observation obs;
  obs.command = Command::kRest;
  EXPECT_EQ(transition(s.model, s.data, obs, s.measured.q), Reason::kUserRest);
  EXPECT_EQ(s.data.state, ModuleState::kRest);
  // The rest set-point starts at the face of the reference.
  EXPECT_LT(
      (s.data.setpoint - robot::dh_club_pose(s.model.arm(), s.data.q_ref).translation()).norm(),
      1e-12);
  Stages idle;
  robot::Vector7 q = idle.measured.q;
  q[1] += 0.01;
  EXPECT_EQ(transition(idle.model, idle.data, Observation{}, q), Reason::kNoChange);
  EXPECT_EQ(idle.data.q_ref, q);  // in Idle the reference is the measurement
}

TEST(ModuleStages, ReferenceMovesTheRestSetPointAtMostTheRestSpeed) {
  Stages s;
  Observation obs;
  obs.command = Command::kRest;
  transition(s.model, s.data, obs, s.measured.q);
  const Eigen::Vector3d before = s.data.setpoint;
  const robot::FaceTarget target = reference(s.model, s.data, s.measured);
  const double step = (s.data.setpoint - before).norm();
  EXPECT_GT(step, 0.0);
  EXPECT_LE(step, s.model.rest_speed() * s.model.config().core_period() + 1e-15);
  EXPECT_EQ(target.position, s.data.setpoint);
  EXPECT_EQ(target.velocity, robot::Vector6::Zero());
  EXPECT_FALSE(s.data.at_rest_pose);  // the goal is still ahead
}

TEST(ModuleStages, TrackIntegratesTheReferenceTowardTheTarget) {
  Stages s;
  robot::FaceTarget target;
  const Eigen::Isometry3d face = robot::dh_club_pose(s.model.arm(), s.data.q_ref);
  target.position = face.translation() + Eigen::Vector3d(0.0, 0.0, 0.01);  // [m] 1 cm up
  target.heading = std::atan2(face.linear()(1, 0), face.linear()(0, 0));
  const robot::Vector7 q_before = s.data.q_ref;
  EXPECT_NE(track(s.model, s.data, target), robot::RtStatus::kInvalidInput);
  EXPECT_TRUE(s.data.qd_des.allFinite());
  const double dt = s.model.config().core_period();
  EXPECT_LT((s.data.q_ref - (q_before + s.data.qd_des * dt)).norm(), 1e-15);
  // The face moved up, by a little (the FIR starts from rest).
  const double dz =
      robot::dh_club_pose(s.model.arm(), s.data.q_ref).translation().z() - face.translation().z();
  EXPECT_GT(dz, 0.0);
  EXPECT_LT(dz, 0.01);
}

TEST(ModuleStages, HoldZeroesTheTrackingState) {
  Stages s;
  s.data.qd_des.setConstant(0.1);
  s.data.qdd_des.setConstant(1.0);
  s.data.integral.setConstant(0.01);
  hold(s.model, s.data, s.measured);
  EXPECT_EQ(s.data.qd_des, robot::Vector7::Zero());
  EXPECT_EQ(s.data.qdd_des, robot::Vector7::Zero());
  EXPECT_EQ(s.data.integral, robot::Vector7::Zero());
}

TEST(ModuleStages, TorqueIsGravityInIdleAndClampedToTheLimits) {
  Stages s;
  robot::Vector7 g;
  ASSERT_EQ(robot::gravity_torque(s.model.arm(), s.measured.q, g), robot::RtStatus::kOk);
  const TorqueOutput idle = torque(s.model, s.data, s.measured);
  EXPECT_FALSE(idle.failed);
  EXPECT_LT((idle.tau - g).norm(), 1e-12);
  // Far from the reference in Rest, the PID asks for more than the motors have.
  s.data.state = ModuleState::kRest;
  s.data.q_ref = s.measured.q;
  s.data.q_ref[1] += 1.0;  // [rad]
  const TorqueOutput far = torque(s.model, s.data, s.measured);
  EXPECT_TRUE(far.clamped);
  for (int j = 0; j < 7; ++j) EXPECT_LE(std::abs(far.tau[j]), s.model.arm().torque_limit()[j]);
  EXPECT_EQ(s.data.tau, far.tau);
  // An unusable measurement gives zero torque.
  s.measured.qd[2] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(torque(s.model, s.data, s.measured).tau, robot::Vector7::Zero());
}

}  // namespace
}  // namespace mg::control
