#include "sim/world.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "sim/putt.hpp"
#include "sim_test_util.hpp"

namespace mg::sim {
namespace {

// The drawn heightfield holds the field's function (ray cast straight down at grid vertices).
TEST(World, HeightfieldHoldsTheSurface) {
  for (const char* name : {"multiple-hills", "regular-hill", "arctan"}) {
    const World world(field::load_field(name));
    auto d = world.make_data();
    const auto& f = world.field();
    const mjModel* m = world.model();
    const int ncol = m->hfield_ncol[0], nrow = m->hfield_nrow[0];
    const mjtByte groups[mjNGROUP] = {1, 1, 1, 1, 1, 1};
    int checked = 0;
    for (int r = 3; r < nrow - 3; r += 7)
      for (int c = 3; c < ncol - 3; c += 11) {
        const double x = f.bounds[0] + (f.bounds[1] - f.bounds[0]) * c / (ncol - 1);
        const double y = f.bounds[2] + (f.bounds[3] - f.bounds[2]) * r / (nrow - 1);
        if (std::hypot(x - f.tee[0], y - f.tee[1]) < 0.3 ||
            std::hypot(x - f.hole.position[0], y - f.hole.position[1]) < 0.1)
          continue;  // skip the ball, its contact box and the cup
        const mjtNum start[3] = {x, y, 2.0}, down[3] = {0, 0, -1};
        int geom = -1;
        const double dist = mj_ray(m, d.get(), start, down, groups, 1, -1, &geom);
        ASSERT_EQ(geom, world.ids().surface_geom) << name;
        EXPECT_NEAR(2.0 - dist, f.height(x, y), 2e-5 + 1e-6 * std::abs(f.height(x, y))) << name;
        ++checked;
      }
    EXPECT_GT(checked, 20);
  }
}

TEST(World, MovingTheHoleChangesDataNotModel) {
  const World world(field::load_field("flat"));
  auto d = world.make_data();
  const mjModel* model_before = world.model();
  const int nbody = world.model()->nbody;
  world.set_hole(d.get(), {1.2, 0.3});
  EXPECT_EQ(world.model(), model_before);
  EXPECT_EQ(world.model()->nbody, nbody);
  EXPECT_EQ(world.hole_position(d.get())[0], 1.2);
  mj_forward(world.model(), d.get());
  const mjtNum* floor = d->geom_xpos + 3 * world.ids().hole_floor_geom;
  EXPECT_DOUBLE_EQ(floor[0], 1.2);
  EXPECT_DOUBLE_EQ(floor[1], 0.3);
  EXPECT_DOUBLE_EQ(floor[2], -world.field().hole.depth - 0.005);  // cylinder centre
}

TEST(World, HoleOutsideTheLaneOrOnASteepSlopeIsAnError) {
  const World world(field::load_field("flat"));
  auto d = world.make_data();
  EXPECT_THROW(world.set_hole(d.get(), {2.68, 0.0}), InputError);
  EXPECT_THROW(world.set_hole(d.get(), {1.0, -0.59}), InputError);
  EXPECT_THROW(world.set_hole(d.get(), {NAN, 0.0}), InputError);
  const World steep(testing::plane_field(0.3, 0.0, 0.131, 0.01));
  EXPECT_THROW(steep.make_data(), InputError);
}

// Contacts come from the model alone: building worlds of either ground sets no MuJoCo callback.
TEST(World, SetsNoProcessWideMujocoCallback) {
  for (GroundContact g : {GroundContact::kTangentPlane, GroundContact::kHeightfield}) {
    WorldOptions o;
    o.ground = g;
    const World world(field::load_field("bank-shot"), o);
    auto d = world.make_data();
    world.step(d.get());
  }
  EXPECT_EQ(mjcb_contactfilter, nullptr);
  EXPECT_EQ(mju_user_error, nullptr);
}

// With MuJoCo's heightfield contacts the ground is cut away over the hole opening as with the
// tangent plane: no ball-ground contact while the ball's centre is over it, and the straight putt
// that sinks on flat ground sinks.
TEST(World, HeightfieldGroundOpensOverTheHole) {
  WorldOptions o;
  o.ground = GroundContact::kHeightfield;
  const World world(field::load_field("flat"), o);
  auto d = world.make_data();
  const auto hole = world.field().hole.position;
  const double r = 0.5 * world.field().hole.diameter;
  world.place_ball(d.get(), {hole[0] + 0.5 * r, hole[1]});
  for (int k = 0; k < 5; ++k) world.step(d.get());
  for (int i = 0; i < d->ncon; ++i) EXPECT_FALSE(world.is_ball_ground(d->contact[i]));
  world.place_ball(d.get(), {hole[0] + 2.0 * r, hole[1]});
  for (int k = 0; k < 5; ++k) world.step(d.get());
  int ground = 0;
  for (int i = 0; i < d->ncon; ++i) ground += world.is_ball_ground(d->contact[i]);
  EXPECT_GT(ground, 0);

  PuttRequest q;
  q.speed = 2.55;
  EXPECT_TRUE(simulate_putt(world, d.get(), hole, q).sunk);
  q.speed = 1.0;
  EXPECT_FALSE(simulate_putt(world, d.get(), hole, q).sunk);
}

TEST(World, OptionsAreValidated) {
  WorldOptions o;
  o.timestep = 0.01;
  EXPECT_THROW(World(field::load_field("flat"), o), InputError);
}

}  // namespace
}  // namespace mg::sim
