#include "sim/world_mjcf.hpp"

#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace mg::sim {
namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The tangent-plane world collides predefined pairs only: every pair holds the ball (statics
// never touch each other), the ball meets the ground box, no border (sim/walls collides them),
// and the drawn heightfield is in none.
TEST(WorldMjcf, TangentPlanePairsAreTheBallsOnly) {
  const field::Field f = field::load_field("flat");
  const WorldOptions o;
  const ModelPtr reference = compile_mjcf(world_mjcf(f, o, ""));
  const std::string pairs = predefined_pairs(reference.get());
  const int n = count(pairs, "<pair ");
  EXPECT_EQ(n, count(pairs, "\"ball\""));
  EXPECT_EQ(count(pairs, "geom1=\"ground\" geom2=\"ball\""), 1);
  for (const char* border : {"border_x_min", "border_x_max", "border_y_min", "border_y_max"})
    EXPECT_EQ(count(pairs, border), 0) << border;
  EXPECT_EQ(count(pairs, "lane_surface"), 0);
  const ModelPtr model = compile_mjcf(world_mjcf(f, o, pairs));
  EXPECT_EQ(model->npair, n);
  EXPECT_EQ(model->opt.collision, mjCOL_PAIR);
}

// The heightfield world: the drawn lane never collides; an invisible copy in a mocap body does,
// through one predefined pair, with the borders in the next body (MuJoCo's collision order).
TEST(WorldMjcf, HeightfieldGroundIsAMocapCopyOfTheLane) {
  WorldOptions o;
  o.ground = GroundContact::kHeightfield;
  const ModelPtr m = compile_mjcf(world_mjcf(field::load_field("flat"), o, ""));
  const int lane = mj_name2id(m.get(), mjOBJ_GEOM, "lane_surface");
  const int copy = mj_name2id(m.get(), mjOBJ_GEOM, "lane_contact");
  ASSERT_GE(copy, 0);
  EXPECT_EQ(m->geom_contype[lane], 0);
  EXPECT_NE(m->geom_contype[copy], 0);
  EXPECT_GE(m->body_mocapid[m->geom_bodyid[copy]], 0);
  const int walls = m->geom_bodyid[mj_name2id(m.get(), mjOBJ_GEOM, "border_x_max")];
  EXPECT_EQ(walls, m->geom_bodyid[copy] + 1);
  EXPECT_LT(walls, mj_name2id(m.get(), mjOBJ_BODY, "ball"));
  EXPECT_EQ(m->npair, 1);
  EXPECT_EQ(m->opt.collision, mjCOL_ALL);
}

TEST(WorldMjcf, RejectedTextIsAnError) {
  EXPECT_THROW(compile_mjcf("<mujoco><worldbody><geom type=\"nonsense\"/></worldbody></mujoco>"),
               Error);
}

}  // namespace
}  // namespace mg::sim
