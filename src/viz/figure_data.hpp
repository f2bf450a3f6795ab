#pragma once
/// The numbers behind `minigolf plot ds|strength|field|model`, as CSV text for
/// scripts/plots/plot.py (one plotting package, shared with the experiments' report).
#include <array>
#include <string>
#include <vector>

#include "ds/demonstrations.hpp"
#include "ds/hitting_model.hpp"
#include "field/field.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"
#include "system/system.hpp"

namespace mg::viz {

/// A plane through x* for the DS figures: "xz" (side view, y = x*_y) or "xy" (top view,
/// z = x*_z). InputError otherwise.
enum class DsPlane { kXz, kXy };
DsPlane parse_ds_plane(const std::string& name);

/// demo,t,x,y,z,speed,distance: the demonstrations [m, world], |xdot| [m/s], |x - x*| [m].
std::string demonstrations_csv(const std::vector<ds::Demonstration>& demos,
                               const ds::HittingModel& model);
/// k,prior,mx,my,mz,cxx,cxy,cxz,cyy,cyz,czz: the SEDS GMM's position part in the world frame
/// (mean + x*; covariance [m^2]).
std::string gmm_csv(const ds::HittingModel& model);
/// a,b,u,v,speed: the DS velocity (theta = 0, v^d = v(x*), constant modulator) on an n x n grid
/// of the plane, projected onto it [m/s]; a, b the plane's coordinates [m, world]; the grid
/// covers the demonstrations with a margin.
std::string ds_field_csv(const ds::HittingModel& model, const std::vector<ds::Demonstration>& demos,
                         DsPlane plane, int n = 30);
/// demo,distance,speed,strength: along each demonstration, its speed and the model's strength
/// factor v(x - x*) [m/s].
std::string strength_csv(const ds::HittingModel& model,
                         const std::vector<ds::Demonstration>& demos);
/// r,s_constant_V,s_sine_V for each v^d in `speeds`: the speed modulators (eqs. 2.6a-d) with
/// d0 = the demonstrations' mean start distance, r from 0 to 1.2 d0.
std::string modulators_csv(const ds::HittingModel& model,
                           const std::vector<ds::Demonstration>& demos,
                           const std::vector<double>& speeds);

/// x,y,z: the field's height on a 2 cm grid.
std::string heights_csv(const field::Field& field);
/// The corners of an obstacle's footprint [m, world], counter-clockwise.
std::array<std::array<double, 2>, 4> footprint_corners(const field::Obstacle& obstacle);
/// obstacle,block,x,y: every obstacle's footprint corners (4 rows each, counter-clockwise;
/// block 1 for a block, 0 for a wall). Header only for a field without obstacles.
std::string obstacles_csv(const field::Field& field);
/// t,x,y,z,vx,vy,vz of a ball-only putt sampled every 10 ms.
std::string trajectory_csv(const sim::PuttOutcome& outcome);

/// inputs..., NAME_mean, NAME_std for every output: the model's prediction on a grid (101 points
/// for one input, 41 x 41 for two) over the data's input range with a 10 % margin. InputError
/// unless the model has 1 or 2 inputs.
std::string predictions_csv(const learning::Model& model, const learning::Dataset& data);

}  // namespace mg::viz
