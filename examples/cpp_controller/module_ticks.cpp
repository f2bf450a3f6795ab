// The controller alone, as a driver for another arm would use it: the module model from the
// arm's published parameters and a hitting model file, a fake arm (the DH model's own rigid-body
// dynamics, integrated here) and a fake camera, then read -> module_update -> write for a rest
// pose and a hit. No simulator: this program is built against minigolf::controller only.
//
//   module_ticks [hitting-model.json]     (default: the installed data's hitting-default.json)
//
// Prints one line per state change and a summary; exits 1 if the module does not go
// Idle -> Rest -> Hitting -> Braking, 2 on bad input.
#include <minigolf/controller.hpp>

#include <cstdio>
#include <exception>
#include <string>

namespace {

constexpr double kBallRadius = 0.021335;  // [m] a golf ball

/// An arm that is not a simulator: M(q) qdd = tau - c(q, qd) - g(q) - damping qd (the robot
/// library's RNEA), semi-implicit Euler at 1 kHz, two steps per 2 ms core tick. The ball waits
/// at the hitting point until the club face's plane reaches it, then leaves along the face
/// normal. The camera reports it every 5th tick (the robot update's rate).
class FakeArm final : public mg::control::ArmBackend {
 public:
  FakeArm(const mg::robot::ArmModel& arm, const Eigen::Vector3d& ball) : arm_(arm), ball_(ball) {
    for (int j = 0; j < 7; ++j) q_[j] = mg::robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
  }
  mg::control::MeasuredState read() noexcept override {
    mg::control::MeasuredState s;
    s.time = time_;
    s.q = q_;
    s.qd = qd_;
    if (ticks_ % 5 == 0) {
      mg::perception::Perceived seen;
      seen.fresh = true;
      seen.age = 0.0;
      seen.ball = {ball_.x(), ball_.y(), ball_.z()};
      seen.hole = {2.0, 0.0, 0.0};
      s.perception = seen;
    }
    return s;
  }
  void write(const mg::control::ModuleCommand& command) noexcept override { tau_ = command.tau; }

  /// Two 1 ms steps under the last torques.
  void advance() {
    for (int k = 0; k < 2; ++k) {
      mg::robot::Matrix7 m;
      mg::robot::Vector7 h;
      if (mg::robot::mass_matrix(arm_, q_, m) != mg::robot::RtStatus::kOk ||
          mg::robot::inverse_dynamics(arm_, q_, qd_, mg::robot::Vector7::Zero(), h) !=
              mg::robot::RtStatus::kOk)
        return;
      qd_ += m.ldlt().solve(tau_ - h) * kStep;
      q_ += qd_ * kStep;
      time_ += kStep;
      const Eigen::Isometry3d face = mg::robot::dh_club_pose(arm_, q_);
      const Eigen::Vector3d normal = face.linear().col(0);
      if (!launched_ && (ball_ - face.translation()).dot(normal) < kBallRadius) launched_ = true;
      if (launched_) ball_ += 2.0 * normal * kStep;  // [m/s] about a putt's launch
    }
    ++ticks_;
  }

 private:
  static constexpr double kStep = 0.001;  // [s]
  mg::robot::ArmModel arm_;
  mg::robot::Vector7 q_ = mg::robot::Vector7::Zero();
  mg::robot::Vector7 qd_ = mg::robot::Vector7::Zero();
  mg::robot::Vector7 tau_ = mg::robot::Vector7::Zero();
  Eigen::Vector3d ball_;
  bool launched_ = false;
  double time_ = 0.0;
  long ticks_ = 0;
};

int run(const std::string& hitting_file) {
  using namespace mg::control;
  const ModuleModel model(mg::robot::ArmModel(mg::robot::WamMount{}),
                          mg::ds::read_hitting_model(hitting_file), ControllerConfig{},
                          kBallRadius);
  ModuleData data(model);
  FakeArm arm(model.arm(), model.hitting().x_star());
  module_reset(model, data, arm.read().q);
  request_rest(model, data, 0.0);  // [rad] hitting angle: straight along +x
  ModuleState last = data.state;
  bool asked = false, rest = false, hitting = false, braking = false, finite = true;
  for (int tick = 0; tick < 2500 && !braking; ++tick) {  // 5 s of core ticks
    const ModuleCommand c = control_tick(model, data, arm);
    finite = finite && c.tau.allFinite();
    arm.advance();
    if (!asked && c.state == ModuleState::kRest && data.at_rest_pose && data.time_in_state > 0.2) {
      asked = true;
      request_hit(model, data, 0.0, 1.0);  // [rad], [m/s] club speed at the ball
    }
    if (c.state != last) {
      std::printf("tick %4d: %s -> %s (%s)\n", tick, std::string(to_string(last)).c_str(),
                  std::string(to_string(c.state)).c_str(),
                  std::string(to_string(c.status.reason)).c_str());
      rest = rest || c.state == ModuleState::kRest;
      hitting = hitting || c.state == ModuleState::kHitting;
      braking = braking || c.state == ModuleState::kBraking;
      last = c.state;
    }
  }
  std::printf("module_ticks: rest %d, hitting %d, braking %d, finite torques %d\n", rest, hitting,
              braking, finite);
  return rest && hitting && braking && finite ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string hitting =
        argc > 1 ? argv[1] : (mg::data_dir() / "models" / "hitting-default.json").string();
    return run(hitting);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "module_ticks: error: %s\n", e.what());
    return 2;
  }
}
