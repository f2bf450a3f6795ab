#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "field/field.hpp"
#include "sim/world.hpp"

namespace mg::sim {
namespace {

// The ball waits on the tee while the arm goes to its rest pose (~0.8 s, up to ~1.7 s at large
// angles): on every shipped field it must stay on its spot, so the club meets it where it aims.
TEST(Tee, BallAtRestOnTheTeeStaysPutOnEveryShippedField) {
  for (const auto& name : field::list_shipped_fields()) {
    const World world(field::load_field(name));
    auto d = world.make_data();  // ball at rest on the tee
    const auto tee = world.field().tee;
    const mjtNum* q = d->qpos + world.ids().ball_qpos;
    double drift = 0.0;
    for (int i = 0; i < 3000; ++i) {  // 3 s at 1 ms
      world.step(d.get());
      drift = std::max(drift, std::hypot(q[0] - tee[0], q[1] - tee[1]));
    }
    EXPECT_LT(drift, 1e-3) << name << ": the ball left the tee by " << drift << " m";
    const auto g = world.field().surface.gradient(tee[0], tee[1]);
    EXPECT_LT(std::hypot(g[0], g[1]), 1e-9) << name << ": the tee is not level";
  }
}

}  // namespace
}  // namespace mg::sim
