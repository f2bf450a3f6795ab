// The core side of a console session: what runs on the real-time core thread (commands applied,
// ticks, events, record samples, the published snapshot) allocates nothing; the snapshot and the
// channels carry what the core did.
#include "system/session_core.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "system/system.hpp"

// Counts heap allocations so the real-time claim is tested, not assumed.
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

namespace mg::system {
namespace {

using control::ModuleState;

struct Rig {
  System system{control::ModuleConfig{}};
  sim::OutcomeTracker tracker = prepared({2.0, 0.0});
  sim::OutcomeTracker other_hole = prepared({1.5, 0.3});
  sim::OutcomeTracker prepared(std::array<double, 2> hole) const {
    const double p[3] = {0.0, 0.0, 1.0}, v[3] = {0.0, 0.0, 0.0};
    sim::OutcomeTracker t(system.arm_world(), hole, sim::OutcomeRules{}, 0.0, p, v);
    t.prepare();
    return t;
  }
};

Rig& rig() {
  static Rig r;
  return r;
}

CoreCommand command(CoreCommand::Kind kind, double a = 0.0, double b = 0.0) {
  CoreCommand c;
  c.kind = kind;
  c.a = a;
  c.b = b;
  return c;
}

// Commands, a whole hit (rest, hit, braking, the ball's outcome), a recording, a new hole and a
// reset: no allocation on the core's side, every event and sample in its ring.
TEST(SessionCore, TheCoreThreadsWorkAllocatesNothing) {
  SessionCore core(rig().system.arm_world(), rig().system.module(), true, nullptr, &rig().tracker);
  using Kind = CoreCommand::Kind;
  const CoreCommand script[] = {command(Kind::kAngle, 0.05), command(Kind::kSpeed, 1.5),
                                command(Kind::kHit)};
  long allocations = 0;
  const auto counted = [&](auto&& work) {
    const long before = g_allocations.load();
    work();
    allocations += g_allocations.load() - before;
  };
  std::uint64_t seq = 0;
  CoreCommand record = command(Kind::kRecord);
  record.on = true;
  for (CoreCommand c : script) {
    c.seq = ++seq;
    ASSERT_TRUE(core.commands.push(c));
  }
  record.seq = ++seq;
  ASSERT_TRUE(core.commands.push(record));
  int events = 0, samples = 0;
  Event e;
  control::RecordSample s;
  for (int k = 0; k < 3000; ++k) {  // 6 s: rest, hit, the roll to its end
    counted([&] {
      core.apply_queued();
      core.tick();
    });
    while (core.events.pop(e)) ++events;
    while (core.samples.pop(s)) ++samples;
  }
  CoreCommand hole = command(Kind::kHole, 1.5, 0.3);
  hole.tracker = &rig().other_hole;
  for (CoreCommand c : {hole, command(Kind::kReset), command(Kind::kIdle)}) {
    c.seq = ++seq;
    counted([&] { core.apply(c); });
  }
  counted([&] { core.tick(); });
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(core.applied.load(), 4u);
  EXPECT_GE(events, 6);          // replies, Idle -> Rest -> Hitting -> Braking -> Idle, the outcome
  EXPECT_NEAR(samples, 600, 2);  // 6 s at the robot rate
  EXPECT_EQ(core.events_lost.load(), 0u);
  const Snapshot& snap = core.snapshot.read();
  EXPECT_EQ(snap.module.state, ModuleState::kIdle);
  ASSERT_TRUE(snap.last_outcome.has_value());
  EXPECT_GT(snap.last_outcome->rest_position[0], 1.0);
  EXPECT_EQ(snap.hole[0], 1.5);
  EXPECT_EQ(snap.ball[0], 0.0);  // back on the tee
  EXPECT_NEAR(snap.time, 3001 * 0.002, 1e-9);
}

}  // namespace
}  // namespace mg::system
