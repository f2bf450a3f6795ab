// The module's core update without the putt driver: no allocation, faults brake, the state
// machine's order Idle -> Rest -> Hitting -> Braking -> Idle.
#include "control/minigolf_module.hpp"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>

#include <gtest/gtest.h>

#include "field/field.hpp"
#include "sim_backend/full_system.hpp"
#include "sim_backend/mujoco_arm.hpp"
#include "sim_backend/simulator_perception.hpp"

// Counts heap allocations so the real-time claim of the core tick is tested, not assumed.
// GCC cannot see that these replacements pair malloc with free.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
namespace {
std::atomic<long> g_allocations{0};
}  // namespace
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
namespace mg::testing {
long allocations() { return g_allocations.load(); }  // for test_arm_interface.cpp
}  // namespace mg::testing

namespace mg::control {
namespace {

struct Bench {
  sim::World world{make_world_with_arm(field::load_field("flat"))};
  ModuleModel model{make_module_model(world,
                                      ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                                             "/data/models/hitting-default.json"),
                                      ModuleConfig{})};
  SimIds ids{find_sim_ids(world)};
  sim::DataPtr data{world.make_data()};
  ModuleData md{model};
  perception::SimulatorPerception truth{world, data.get()};

  Bench() {
    mjData* d = data.get();
    world.reset(d);
    robot::Vector7 q;
    for (int j = 0; j < 7; ++j) q[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
    robot::set_joint_positions(ids.arm, d, q);
    mj_forward(world.model(), d);
    module_reset(model, md, ids.arm, d);
  }
  /// The core tick on the simulated arm: read -> update -> write.
  ModuleCommand core_tick() {
    MujocoArm arm(ids.arm, data.get());
    return control_tick(model, md, arm);
  }
  /// One core tick (with the robot update when due) and two physics steps; returns the
  /// allocations made inside the robot and core updates.
  long tick() {
    const long before = g_allocations.load();
    if (md.tick % model.config().robot_update_divider == 0)
      robot_update(model, md, truth.perceive(data->time));
    core_tick();
    const long made = g_allocations.load() - before;
    world.step(data.get());
    world.step(data.get());
    return made;
  }
  /// Rest at angle 0, hit at 1 m/s, 20 ticks into the hit; true if the module is then Hitting.
  bool start_hit() {
    if (!request_rest(model, md, 0.0)) return false;
    run_until([&] { return md.at_rest_pose; }, 3000);
    if (!request_hit(model, md, 0.0, 1.0)) return false;
    for (int i = 0; i < 20; ++i) tick();
    return md.state == ModuleState::kHitting;
  }
  /// Ticks until `done` or `max_ticks`; returns allocations inside core_update.
  template <class Done>
  long run_until(Done done, int max_ticks) {
    long allocations = 0;
    for (int i = 0; i < max_ticks && !done(); ++i) allocations += tick();
    return allocations;
  }
};

TEST(MinigolfModule, WholeHitCycleWithoutAllocation) {
  Bench b;
  long allocations = 0;
  ASSERT_TRUE(request_rest(b.model, b.md, 0.1));
  allocations +=
      b.run_until([&] { return b.md.state == ModuleState::kRest && b.md.at_rest_pose; }, 3000);
  ASSERT_TRUE(b.md.at_rest_pose);
  ASSERT_TRUE(request_hit(b.model, b.md, 0.1, 1.0));
  allocations += b.tick();
  EXPECT_EQ(b.md.state, ModuleState::kHitting);
  allocations += b.run_until([&] { return b.md.state != ModuleState::kHitting; }, 1500);
  EXPECT_EQ(b.md.state, ModuleState::kBraking);
  EXPECT_EQ(b.md.last.reason, Reason::kBallHit);
  allocations += b.run_until([&] { return b.md.state == ModuleState::kIdle; }, 1500);
  EXPECT_EQ(b.md.state, ModuleState::kIdle);
  EXPECT_EQ(allocations, 0);
  for (int j = 0; j < 7; ++j) EXPECT_TRUE(std::isfinite(b.md.tau[j]));
}

TEST(MinigolfModule, NanMeasurementDuringHitBrakesWithFiniteTorques) {
  Bench b;
  ASSERT_TRUE(b.start_hit());
  b.data->qvel[b.ids.arm.dof[3]] = std::numeric_limits<double>::quiet_NaN();
  b.core_tick();
  EXPECT_EQ(b.md.state, ModuleState::kBraking);
  EXPECT_EQ(b.md.last.reason, Reason::kFault);
  for (int j = 0; j < 7; ++j) {
    const double u = b.data->ctrl[b.ids.arm.actuator[static_cast<std::size_t>(j)]];
    EXPECT_TRUE(std::isfinite(u)) << j;
    EXPECT_LE(std::abs(u), b.model.arm().torque_limit()[j]) << j;
  }
}

TEST(MinigolfModule, HitRefusedUnlessAtRest) {
  Bench b;
  ASSERT_TRUE(request_rest(b.model, b.md, 0.0));
  b.tick();
  ASSERT_EQ(b.md.state, ModuleState::kRest);
  request_hit(b.model, b.md, 0.0, 1.0);  // the arm has not reached the rest pose of angle 0 yet
  b.tick();
  EXPECT_EQ(b.md.state, ModuleState::kRest);
  EXPECT_EQ(b.md.last.reason, Reason::kHitRefusedNotAtRest);
}

TEST(MinigolfModule, NormalModeRefusesClubSpeedsAboveTheSafetyRule) {
  Bench b;
  ModuleConfig normal;
  normal.mode = ModuleMode::kNormal;
  const ModuleModel model = make_module_model(b.world, b.model.hitting(), normal);
  ModuleData md(model);
  module_reset(model, md, b.ids.arm, b.data.get());
  ASSERT_TRUE(request_rest(model, md, 0.0));
  EXPECT_FALSE(request_hit(model, md, 0.0, robot::kSafeEndpointSpeed + 0.1));
  EXPECT_TRUE(request_hit(model, md, 0.0, robot::kSafeEndpointSpeed));
  EXPECT_LE(model.club_speed_cap(), robot::kSafeEndpointSpeed);
  // the simulator-mode model accepts the faster request
  ASSERT_TRUE(request_rest(b.model, b.md, 0.0));
  EXPECT_TRUE(request_hit(b.model, b.md, 0.0, robot::kSafeEndpointSpeed + 0.1));
}

TEST(MinigolfModule, RestPoseIsBehindTheBallAlongTheHittingDirection) {
  Bench b;
  for (double a : {-0.5, 0.0, 0.3}) {
    const Eigen::Vector3d rest = rest_face_position(b.model, a);
    const Eigen::Vector3d psi(std::cos(a), std::sin(a), 0.0);
    const Eigen::Vector3d rel = rest - b.model.hitting().x_star();
    EXPECT_LT(rel.dot(psi), -0.1) << a;                                         // behind the ball
    EXPECT_NEAR((rel - rel.dot(psi) * psi).head<2>().norm(), 0.0, 1e-12) << a;  // on the line
  }
}

}  // namespace
}  // namespace mg::control

namespace mg::control {
namespace {

TEST(MinigolfModule, OverrunStreakFaultBrakesAHit) {
  Bench b;
  ASSERT_TRUE(b.start_hit());
  b.md.overrun_fault = true;  // what the real-time scheduler sets after a streak of misses
  b.tick();
  EXPECT_EQ(b.md.state, ModuleState::kBraking);
  EXPECT_EQ(b.md.last.reason, Reason::kFault);
  b.run_until([&] { return b.md.state == ModuleState::kIdle; }, 1500);
  EXPECT_EQ(b.md.state, ModuleState::kIdle);
  // Still faulted: a new hit is not started until the module is reset.
  ASSERT_TRUE(request_rest(b.model, b.md, 0.0));
  b.tick();
  EXPECT_EQ(b.md.state, ModuleState::kIdle);
}

}  // namespace
}  // namespace mg::control

namespace mg::control {
namespace {

// Idle is gravity compensation: the arm stays where it is left (the controller's model equals the
// plant, so any drift would be a modelling error).
TEST(MinigolfModule, IdleHoldsTheArmWhereItIsLeft) {
  Bench b;
  robot::Vector7 q;
  q << 0.3, -0.4, 0.2, 1.2, -0.3, 0.4, 0.1;
  robot::set_joint_positions(b.ids.arm, b.data.get(), q);
  mj_forward(b.world.model(), b.data.get());
  module_reset(b.model, b.md, b.ids.arm, b.data.get());
  for (int i = 0; i < 500; ++i) b.tick();  // 1 s
  EXPECT_EQ(b.md.state, ModuleState::kIdle);
  const robot::Vector7 after = robot::joint_positions(b.ids.arm, b.data.get());
  EXPECT_LT((after - q).cwiseAbs().maxCoeff(), 1e-3) << (after - q).transpose();
}

}  // namespace
}  // namespace mg::control
