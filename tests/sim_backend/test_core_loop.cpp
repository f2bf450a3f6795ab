// The one core loop: its tick (read -> robot update on the divider -> module update -> write ->
// physics steps with hooks), its timing histogram, and a hook's exception as a fault.
#include "sim_backend/core_loop.hpp"

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "field/field.hpp"
#include "robot/wam_model.hpp"
#include "sim_backend/full_system.hpp"
#include "sim_backend/mujoco_arm.hpp"

namespace mg::testing {
long allocations();  // count_allocations.cpp counts operator new
}  // namespace mg::testing

namespace mg::control {
namespace {

struct Rig {
  sim::World world{make_world_with_arm(field::load_field("flat"))};
  ModuleModel model{make_module_model(world,
                                      ds::read_hitting_model(std::string(MINIGOLF_SOURCE_DIR) +
                                                             "/data/models/hitting-default.json"),
                                      ModuleConfig{})};
  /// A simulation with the arm at its default rest posture.
  sim::DataPtr rest_data() const {
    sim::DataPtr d = world.make_data();
    world.reset(d.get());
    robot::Vector7 q;
    for (int j = 0; j < 7; ++j) q[j] = robot::kDefaultRestPosture[static_cast<std::size_t>(j)];
    robot::set_joint_positions(find_sim_ids(world).arm, d.get(), q);
    mj_forward(world.model(), d.get());
    return d;
  }
};

Rig& rig() {
  static Rig r;
  return r;
}

/// Records what the loop called, in order.
class Trace final : public CoreHooks {
 public:
  void after_robot_update(const MeasuredState& measured, ModuleData&) override {
    calls += "R";
    robot_times.push_back(measured.time);
  }
  void after_tick(const ModuleCommand&, ModuleState) override { calls += "T"; }
  void before_step(long) override { calls += "("; }
  void after_step(long) override { calls += ")"; }
  std::string calls;
  std::vector<double> robot_times;
};

TEST(CoreLoop, ATickIsReadRobotUpdateOnTheDividerUpdateWriteThenTheSteps) {
  auto d = rig().rest_data();
  CoreLoop loop(rig().world, rig().model, d.get());
  Trace trace;
  loop.set_hooks(&trace);
  ASSERT_EQ(loop.steps_per_tick(), 2);
  for (int k = 0; k < 6; ++k) loop.tick();
  // The robot update on ticks 0 and 5 (robot_update_divider 5), before that tick's update.
  EXPECT_EQ(trace.calls, "RT()()T()()T()()T()()T()()RT()()");
  EXPECT_EQ(loop.steps(), 12);
  EXPECT_EQ(loop.ticks(), 6u);
  EXPECT_EQ(loop.module().tick, 6);
  ASSERT_EQ(trace.robot_times.size(), 2u);
  EXPECT_DOUBLE_EQ(trace.robot_times[1], 10 * rig().world.model()->opt.timestep);
  EXPECT_EQ(loop.timing().ticks, 6);
}

// The loop is the module's functions in the documented order: the same bits as calling them by
// hand (robot update, control_tick on the simulated arm, the physics step).
TEST(CoreLoop, GivesTheBitsOfTheModuleFunctionsCalledByHand) {
  const ModuleModel& model = rig().model;
  auto a = rig().rest_data();
  auto b = rig().rest_data();
  CoreLoop loop(rig().world, model, a.get());
  ModuleData md(model);
  const SimIds ids = find_sim_ids(rig().world);
  module_reset(model, md, ids.arm, b.get());
  perception::SimulatorPerception truth(rig().world, b.get());
  request_rest(model, loop.module(), 0.1);
  request_rest(model, md, 0.1);
  for (int k = 0; k < 600; ++k) {
    loop.tick();
    if (md.tick % model.config().robot_update_divider == 0)
      robot_update(model, md, truth.perceive(b->time));
    MujocoArm arm(ids.arm, b.get());
    control_tick(model, md, arm);
    for (int s = 0; s < 2; ++s) physics_step(rig().world, ids, b.get());
  }
  const int nq = rig().world.model()->nq, nv = rig().world.model()->nv;
  EXPECT_TRUE(std::equal(a->qpos, a->qpos + nq, b->qpos));
  EXPECT_TRUE(std::equal(a->qvel, a->qvel + nv, b->qvel));
  EXPECT_EQ(loop.module().state, ModuleState::kRest);
}

/// Throws from one of its hooks once the module is in `when`.
class Thrower final : public CoreHooks {
 public:
  Thrower(int where, ModuleState when, const CoreLoop& loop)
      : where_(where), when_(when), loop_(&loop) {}
  void after_robot_update(const MeasuredState&, ModuleData&) override { maybe(0); }
  void after_tick(const ModuleCommand&, ModuleState) override { maybe(1); }
  void before_step(long) override { maybe(2); }
  void after_step(long) override { maybe(3); }
  int thrown = 0;

 private:
  void maybe(int where) {
    if (where != where_ || loop_->module().state != when_ || thrown > 0) return;
    ++thrown;
    if (where == 3) throw 42;  // not even a std::exception
    throw std::runtime_error("hook " + std::to_string(where));
  }
  int where_;
  ModuleState when_;
  const CoreLoop* loop_;
};

// A hook that throws, wherever it is called, never leaves the loop: the module latches a fault
// and brakes, the loop reports it and runs on.
TEST(CoreLoop, AHooksExceptionIsAFaultThatBrakesTheArm) {
  for (int where = 0; where < 4; ++where) {
    auto d = rig().rest_data();
    CoreLoop loop(rig().world, rig().model, d.get());
    Thrower thrower(where, ModuleState::kRest, loop);
    loop.set_hooks(&thrower);
    request_rest(rig().model, loop.module(), 0.1);
    for (int k = 0; k < 250; ++k) loop.tick();
    ASSERT_EQ(thrower.thrown, 1) << where;
    EXPECT_EQ(loop.fault().count, 1u) << where;
    EXPECT_STREQ(loop.fault().what.data(), where == 3 ? "an exception of unknown type"
                                                      : ("hook " + std::to_string(where)).c_str());
    EXPECT_TRUE(loop.module().hook_fault);
    EXPECT_NE(loop.module().state, ModuleState::kRest) << where;  // braking, then idle
    EXPECT_EQ(loop.steps(), 500);                                 // the physics went on
    // Cleared only by a reset.
    module_reset(rig().model, loop.module(), loop.ids().arm, d.get());
    EXPECT_FALSE(loop.module().hook_fault);
  }
}

// Real-time contract: a tick (read, robot update, module update, write, the physics steps, the
// hooks) allocates nothing, through the rest pose, the hit and the braking.
TEST(CoreLoop, ATickAllocatesNothing) {
  auto d = rig().rest_data();
  CoreLoop loop(rig().world, rig().model, d.get());
  Trace trace;
  trace.calls.reserve(1 << 16);
  trace.robot_times.reserve(1 << 12);
  loop.set_hooks(&trace);
  request_rest(rig().model, loop.module(), 0.0);
  long allocations = 0;
  bool hit = false;
  for (int k = 0; k < 1500; ++k) {
    if (!hit && loop.module().at_rest_pose) hit = request_hit(rig().model, loop.module(), 0.0, 1.0);
    const long before = mg::testing::allocations();
    loop.tick();
    allocations += mg::testing::allocations() - before;
  }
  EXPECT_TRUE(hit);
  EXPECT_NE(loop.module().state, ModuleState::kRest);
  EXPECT_EQ(allocations, 0);
}

TEST(CoreLoop, RestoreContinuesWithTheSameBits) {
  auto a = rig().rest_data();
  CoreLoop loop(rig().world, rig().model, a.get());
  request_rest(rig().model, loop.module(), 0.2);
  for (int k = 0; k < 100; ++k) loop.tick();
  auto saved = rig().world.make_data();
  mj_copyData(saved.get(), rig().world.model(), a.get());
  const ModuleData module = loop.module();
  const long steps = loop.steps();
  for (int k = 0; k < 100; ++k) loop.tick();
  std::vector<double> first(a->qpos, a->qpos + rig().world.model()->nq);

  mj_copyData(a.get(), rig().world.model(), saved.get());
  loop.restore(module, steps);
  EXPECT_EQ(loop.timing().ticks, 0);
  for (int k = 0; k < 100; ++k) loop.tick();
  EXPECT_EQ(first, std::vector<double>(a->qpos, a->qpos + rig().world.model()->nq));
}

TEST(TimingHistogram, BinsCoverEveryDurationWithinOnePercent) {
  for (std::int64_t ns :
       {0LL, 1LL, 255LL, 256LL, 257LL, 511LL, 512LL, 2800LL, 123456LL, (1LL << 27) + 5}) {
    const int b = TimingHistogram::bin_of(ns);
    ASSERT_GE(b, 0);
    ASSERT_LT(b, TimingHistogram::kBins);
    EXPECT_LE(TimingHistogram::bin_lower(b), ns);
    EXPECT_GT(TimingHistogram::bin_lower(b) + TimingHistogram::bin_width(b), ns);
    EXPECT_LE(static_cast<double>(TimingHistogram::bin_width(b)),
              std::max(1.0, 0.008 * static_cast<double>(ns)));
  }
  EXPECT_EQ(TimingHistogram::bin_of(std::int64_t{1} << 40), TimingHistogram::kBins - 1);
  for (int b = 1; b < TimingHistogram::kBins; ++b)
    ASSERT_EQ(TimingHistogram::bin_lower(b),
              TimingHistogram::bin_lower(b - 1) + TimingHistogram::bin_width(b - 1));
}

// The summary against a sorted list of the same samples (what the putt harness reported before).
TEST(TimingHistogram, SummaryMatchesTheSortedSamples) {
  std::mt19937_64 rng(3);
  std::lognormal_distribution<double> dist(8.0, 0.6);  // ~3 us, a tail past 2 ms
  std::vector<std::int64_t> samples(20000);
  TimingHistogram h;
  for (auto& s : samples) {
    s = static_cast<std::int64_t>(dist(rng));
    h.add(s, 10'000);
  }
  std::sort(samples.begin(), samples.end());
  const CoreTiming t = h.summary();
  const double p99 = static_cast<double>(samples[static_cast<std::size_t>(0.99 * 20000)]) * 1e-3;
  EXPECT_EQ(t.ticks, 20000);
  EXPECT_GE(t.core_update_p99_us, p99);
  EXPECT_LE(t.core_update_p99_us, p99 * 1.008 + 1e-3);
  EXPECT_DOUBLE_EQ(t.core_update_max_us, static_cast<double>(samples.back()) * 1e-3);
  EXPECT_EQ(t.overruns, std::count_if(samples.begin(), samples.end(),
                                      [](std::int64_t s) { return s > 10'000; }));
  h.clear();
  EXPECT_EQ(h.summary().ticks, 0);
}

}  // namespace
}  // namespace mg::control
