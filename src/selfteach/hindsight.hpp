#pragma once
/// Hindsight labels: what one putt's ball path says about *other* hole positions of a region.
///
/// Until it comes near the real hole, a ball rolls as if there were no hole. So a putt
/// (theta, v) whose ball passes a point p of the field at horizontal speed s would, with the hole
/// at p, have reached the hole centre at s: it is the putt of strategy "arrive at s" for the
/// situation p. One putt therefore labels every point of its path up to the real hole:
///   angle and speed  the point where the ball's speed first falls to the strategy's arrival
///                    speed s* (one label; a point where it would sink with room on both sides);
///   angle only       (the club speed is fixed) every point of the path in the region: on a line
///                    region its crossing of the line, in a box one point every `spacing` [m].
/// Whether a label is right is measured by replaying the putt with the hole really there
/// (`replay_label`); the self-teacher corrects s* when labels at its own targets miss.
#include <array>
#include <vector>

#include "field/situations.hpp"
#include "sim/putt.hpp"

namespace mg::selfteach {

/// A hindsight label: the putt (angle, speed) would reach `hole` at `arrival_speed`.
struct Label {
  std::array<double, 2> hole{0, 0};  ///< [m]
  std::array<double, 2> ball{0, 0};  ///< [m] where the putt's ball lay (the situation's ball)
  double angle = 0.0;                ///< [rad] hitting angle of the putt
  double speed = 0.0;                ///< [m/s] club speed of the putt
  double arrival_speed = 0.0;        ///< [m/s] ball speed there
  int putt = -1;                     ///< index of the putt it came from
};

struct HindsightRules {
  bool learn_speed = true;
  double arrival_speed = 0.4;  ///< [m/s] s*, learn_speed only
  double spacing = 0.03;       ///< [m] angle only, non-line regions: along the path
  double min_speed = 0.05;     ///< [m/s] a slower ball has (nearly) stopped: it would not reach
  void validate() const;       ///< InputError naming the field
};

/// Axis-aligned bounds of a region's holes (x0, x1, y0, y1) [m].
std::array<double, 4> region_bounds(const field::Situations& region);

/// The margin labels are kept within [m]: 5 cm + a quarter of the region's larger extent (labels
/// just outside help the model at the region's edges).
double label_margin(const field::Situations& region);

/// Where labels may lie: the region's bounds grown by `margin` [m] on every side.
bool in_label_zone(const field::Situations& region, std::array<double, 2> p, double margin);

/// The labels of one putt from `ball` [m]. `trajectory`: its ball samples (time order) from the
/// launch on; `real_hole` and `hole_radius` [m]: where the hole was. The path is used until the
/// ball's centre first comes within `hole_radius` of it; from there it is continued straight for 2
/// hole radii plus 2 cm, slowing at `rolling_decel` [m/s^2] (the real hole's own neighbourhood, so
/// a putt that sank labels its own target). Labels lie within `margin` of the region.
std::vector<Label> hindsight_labels(const std::vector<sim::BallSample>& trajectory,
                                    std::array<double, 2> ball, std::array<double, 2> real_hole,
                                    double hole_radius, double rolling_decel,
                                    const field::Situations& region, double margin, double angle,
                                    double speed, int putt, const HindsightRules& rules);

}  // namespace mg::selfteach
