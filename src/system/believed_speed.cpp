#include "system/believed_speed.hpp"

#include <algorithm>

#include "belief/speed_choice.hpp"

namespace mg::system {

double believed_club_speed(const System& system, const field::Situation& situation,
                           double equivalent_speed, double angle) {
  const plant::Plant& believed = system.belief();
  if (believed.empty()) return equivalent_speed;
  // The robot's ball world: the believed field with the simulator's options of its own worlds.
  const sim::World world(system.field(), system.ball_world().options());
  belief::SpeedChoiceOptions o;
  // The launch as the robot's own arm model gives it, with the arm it believes in.
  o.launch_per_club = belief::kArmLaunchPerCommand * believed.arm.club_speed_scale;
  o.launch_angle_bias = belief::kArmLaunchAngleOffset + believed.arm.launch_angle_bias;
  o.speed_min = system.config().speed_min;
  o.speed_max = std::min(system.config().speed_max, system.module().club_speed_cap());
  return belief::choose_club_speed(world, situation.ball, situation.hole, angle, equivalent_speed,
                                   o)
      .club_speed;
}

}  // namespace mg::system
