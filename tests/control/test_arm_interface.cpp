// The control boundary without MuJoCo: a fake arm (rigid-body dynamics of robot/dynamics,
// integrated here) and a fake camera drive the module through read -> update -> write, Rest ->
// Hitting -> Braking -> Idle, with the hit detected from measurements only.
#include "control/arm_interface.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "control/minigolf_module.hpp"
#include "ds/hitting_model.hpp"
#include "robot/dynamics.hpp"
#include "robot/wam_model.hpp"

namespace mg::testing {
long allocations();  // test_minigolf_module.cpp counts operator new
}

namespace mg::control {
namespace {

constexpr double kBallRadius = 0.021335;

/// A simulated arm that is not MuJoCo: M(q) qdd = tau - c(q, qd) - g(q) - damping qd from our own
/// RNEA, semi-implicit Euler at 1 kHz (2 steps per 2 ms tick). A ball at rest at `ball` that
/// leaves along the face normal at 1.6x the face speed when the face plane reaches it; the camera
/// reports it (fresh, age 0) every 5th tick.
class FakeArm final : public ArmBackend {
 public:
  FakeArm(const robot::ArmModel& arm, const Eigen::Vector3d& ball) : arm_(arm), ball_(ball) {
    for (int j = 0; j < 7; ++j) q_[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  }

  MeasuredState read() noexcept override {
    MeasuredState s;
    s.time = time_;
    s.q = q_ + q_offset_;
    s.qd = qd_;
    if (ticks_ % 5 == 0 && camera_on_) {
      perception::Perceived p;
      p.fresh = true;
      p.age = 0.0;
      p.ball = {ball_.x(), ball_.y(), ball_.z()};
      p.hole = {2.0, 0.0, 0.0};
      s.perception = p;
    }
    return s;
  }
  void write(const ModuleCommand& command) noexcept override {
    tau_ = command.tau;
    ++writes_;
  }

  /// Two 1 ms plant steps under the last torques; the ball rolls on (no friction).
  void advance() {
    for (int k = 0; k < 2; ++k) {
      robot::Matrix7 m;
      robot::Vector7 h;
      ASSERT_EQ(robot::mass_matrix(arm_, q_, m), robot::RtStatus::kOk);
      ASSERT_EQ(robot::inverse_dynamics(arm_, q_, qd_, robot::Vector7::Zero(), h),
                robot::RtStatus::kOk);
      const robot::Vector7 qdd = m.ldlt().solve(tau_ - h);
      qd_ += qdd * kStep;
      q_ += qd_ * kStep;
      time_ += kStep;
      const Eigen::Isometry3d face = robot::dh_club_pose(arm_, q_);
      const Eigen::Vector3d n = face.linear().col(0);
      if (!launched_ && (ball_ - face.translation()).dot(n) < kBallRadius) {
        robot::Matrix67 jac;
        Eigen::Isometry3d pose;
        robot::dh_club_jacobian(arm_, q_, pose, jac);
        ball_velocity_ = 1.6 * n * (jac.topRows<3>() * qd_).dot(n);
        launched_ = true;
        launch_time_ = time_;
      }
      ball_ += ball_velocity_ * kStep;
    }
    ++ticks_;
  }

  const robot::Vector7& q() const { return q_; }
  const robot::Vector7& tau() const { return tau_; }
  bool launched() const { return launched_; }
  double launch_time() const { return launch_time_; }
  double time() const { return time_; }
  long writes() const { return writes_; }
  void set_camera(bool on) { camera_on_ = on; }
  /// Moves the ball (a bump, a gust) without the club.
  void push_ball(const Eigen::Vector3d& dx) { ball_ += dx; }
  void set_encoder_offset(int joint, double value) { q_offset_[joint] = value; }

 private:
  static constexpr double kStep = 0.001;
  robot::ArmModel arm_;
  robot::Vector7 q_ = robot::Vector7::Zero();
  robot::Vector7 qd_ = robot::Vector7::Zero();
  robot::Vector7 tau_ = robot::Vector7::Zero();
  robot::Vector7 q_offset_ = robot::Vector7::Zero();
  Eigen::Vector3d ball_;
  Eigen::Vector3d ball_velocity_ = Eigen::Vector3d::Zero();
  bool launched_ = false;
  bool camera_on_ = true;
  double launch_time_ = -1.0;
  double time_ = 0.0;
  long ticks_ = 0;
  long writes_ = 0;
};

struct Rig {
  ModuleModel model{robot::ArmModel(robot::WamMount{}),
                    ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                           "/data/models/hitting-default.json"),
                    ModuleConfig{}, kBallRadius};
  ModuleData md{model};
  FakeArm arm{model.arm(), model.hitting().x_star()};
  std::vector<ModuleState> states;  // each state entered, in order
  std::vector<Reason> reasons;      // why
  long allocations = 0;
  long ticks = 0;
  double max_torque_ratio = 0.0;
  bool all_finite = true;

  Rig() {
    module_reset(model, md, arm.q());
    states.push_back(md.state);
    reasons.push_back(Reason::kNoChange);
  }
  ModuleCommand tick() {
    const long before = mg::testing::allocations();
    const ModuleCommand c = control_tick(model, md, arm);
    allocations += mg::testing::allocations() - before;
    if (c.state != states.back()) {
      states.push_back(c.state);
      reasons.push_back(c.status.reason);
    }
    for (int j = 0; j < 7; ++j) {
      all_finite = all_finite && std::isfinite(c.tau[j]);
      max_torque_ratio =
          std::max(max_torque_ratio, std::abs(c.tau[j]) / model.arm().torque_limit()[j]);
    }
    arm.advance();
    ++ticks;
    return c;
  }
  template <class Done>
  void run_until(Done done, int max_ticks) {
    for (int i = 0; i < max_ticks && !done(); ++i) tick();
  }
  /// Rest at `angle`, settle, request the hit; true if the module is then Hitting.
  bool start_hit(double angle, double speed) {
    if (!request_rest(model, md, angle)) return false;
    run_until(
        [&] { return md.state == ModuleState::kRest && md.at_rest_pose && md.time_in_state > 0.2; },
        3000);
    if (!request_hit(model, md, angle, speed)) return false;
    tick();
    return md.state == ModuleState::kHitting;
  }
};

TEST(ArmInterface, FakeArmDrivesRestHitBrakeIdleFromMeasurementsOnly) {
  Rig r;
  ASSERT_TRUE(r.start_hit(0.1, 1.0));
  r.run_until([&] { return r.md.state == ModuleState::kIdle; }, 3000);

  const std::vector<ModuleState> expected{ModuleState::kIdle, ModuleState::kRest,
                                          ModuleState::kHitting, ModuleState::kBraking,
                                          ModuleState::kIdle};
  EXPECT_EQ(r.states, expected);
  ASSERT_EQ(r.reasons.size(), 5u);
  EXPECT_EQ(r.reasons[1], Reason::kUserRest);
  EXPECT_EQ(r.reasons[2], Reason::kUserHit);
  EXPECT_EQ(r.reasons[3], Reason::kBallHit);
  EXPECT_EQ(r.reasons[4], Reason::kStationary);
  EXPECT_EQ(r.md.hit_evidence, HitEvidence::kClubPath);
  EXPECT_TRUE(r.arm.launched());
  EXPECT_EQ(r.allocations, 0);
  EXPECT_TRUE(r.all_finite);
  EXPECT_LE(r.max_torque_ratio, 1.0);
  EXPECT_EQ(r.arm.writes(), r.ticks);  // one read and one write per tick
}

TEST(ArmInterface, HitIsSeenWithinOneTickOfTheFakeBallsLaunch) {
  // The fake launches the ball when the face plane reaches it; the module, from the measured
  // joints, must see it at the first tick after (the braking starts within 2 ms).
  Rig r;
  ASSERT_TRUE(r.start_hit(0.0, 1.5));
  double seen_at = -1.0;
  for (int i = 0; i < 1500 && seen_at < 0.0; ++i) {
    const double t = r.arm.time();
    r.tick();
    if (r.md.ball_hit) seen_at = t;
  }
  ASSERT_TRUE(r.arm.launched());
  ASSERT_GE(seen_at, 0.0);
  EXPECT_GE(seen_at, r.arm.launch_time() - 1e-9);          // not before the face got there
  EXPECT_LE(seen_at, r.arm.launch_time() + 0.002 + 1e-9);  // and at the next tick at the latest
  EXPECT_EQ(r.md.hit_evidence, HitEvidence::kClubPath);
  EXPECT_EQ(r.md.state, ModuleState::kBraking);
}

TEST(ArmInterface, PerceivedBallMotionCountsAsAHit) {
  // The ball is knocked 2 cm sideways before the club gets there: the camera sees it move and
  // the module brakes instead of swinging on.
  Rig r;
  ASSERT_TRUE(r.start_hit(0.0, 0.5));
  for (int i = 0; i < 20; ++i) r.tick();
  ASSERT_EQ(r.md.state, ModuleState::kHitting);
  r.arm.push_ball({0.0, 0.02, 0.0});
  r.run_until([&] { return r.md.state != ModuleState::kHitting; }, 20);
  EXPECT_EQ(r.md.state, ModuleState::kBraking);
  EXPECT_EQ(r.md.last.reason, Reason::kBallHit);
  EXPECT_EQ(r.md.hit_evidence, HitEvidence::kBallMotion);
  EXPECT_FALSE(r.arm.launched());
}

TEST(ArmInterface, BallMotionBelowTheThresholdIsNotAHit) {
  Rig r;
  ASSERT_TRUE(r.start_hit(0.0, 0.5));
  for (int i = 0; i < 20; ++i) r.tick();
  r.arm.push_ball({0.0, 0.5 * r.model.config().ball_moved_distance, 0.0});  // vision noise
  for (int i = 0; i < 20; ++i) r.tick();
  EXPECT_EQ(r.md.state, ModuleState::kHitting);
  EXPECT_FALSE(r.md.ball_hit);
}

TEST(ArmInterface, LostCameraDuringTheHitBrakes) {
  Rig r;
  ASSERT_TRUE(r.start_hit(0.0, 0.5));
  r.arm.set_camera(false);
  r.run_until([&] { return r.md.state != ModuleState::kHitting; }, 500);
  EXPECT_EQ(r.md.state, ModuleState::kBraking);
  EXPECT_EQ(r.md.last.reason, Reason::kFault);
  r.run_until([&] { return r.md.state == ModuleState::kIdle; }, 1500);
  EXPECT_EQ(r.md.state, ModuleState::kIdle);
  EXPECT_TRUE(r.all_finite);
  EXPECT_LE(r.max_torque_ratio, 1.0);
}

TEST(ArmInterface, BrokenEncoderGivesAFiniteCommandAndBrakes) {
  Rig r;
  ASSERT_TRUE(r.start_hit(0.0, 1.0));
  r.arm.set_encoder_offset(2, std::numeric_limits<double>::quiet_NaN());
  const ModuleCommand c = r.tick();
  EXPECT_EQ(c.state, ModuleState::kBraking);
  EXPECT_TRUE(c.status.fault);
  for (int j = 0; j < 7; ++j) EXPECT_EQ(c.tau[j], 0.0) << j;  // nothing to compute torques from
  EXPECT_EQ(r.allocations, 0);
}

TEST(ArmInterface, ClubReachesBallIsTheHeadBoxAgainstTheBall) {
  const Rig r;
  const robot::ClubGeometry& club = r.model.arm().mount().club;
  const Eigen::Isometry3d face = Eigen::Isometry3d::Identity();  // normal +x, heel +y, up +z
  const auto reaches = [&](double x, double y, double z) {
    return club_reaches_ball(r.model, face, {x, y, z});
  };
  EXPECT_FALSE(reaches(kBallRadius + 1e-6, 0.0, 0.0));  // just in front of the face
  EXPECT_TRUE(reaches(kBallRadius - 1e-6, 0.0, 0.0));   // touching
  EXPECT_TRUE(reaches(-0.2, 0.0, 0.0));                 // the head went through its place
  const double toe = 0.5 * club.head_length;
  EXPECT_TRUE(reaches(0.0, toe + kBallRadius - 1e-6, 0.0));   // at the toe
  EXPECT_FALSE(reaches(0.0, toe + kBallRadius + 1e-6, 0.0));  // beside it: a miss
  const double top = 0.5 * club.head_height;
  EXPECT_FALSE(reaches(0.0, 0.0, top + kBallRadius + 1e-6));  // over the head
  // The corner: within one radius of the edge, diagonally.
  const double d = kBallRadius / std::sqrt(2.0);
  EXPECT_TRUE(reaches(d - 1e-6, toe + d - 1e-6, 0.0));
  EXPECT_FALSE(reaches(d + 1e-6, toe + d + 1e-6, 0.0));
  EXPECT_FALSE(reaches(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0));
}

}  // namespace
}  // namespace mg::control
