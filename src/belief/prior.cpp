#include "belief/prior.hpp"

#include <algorithm>
#include <cmath>

#include "belief/path_fit.hpp"
#include "belief/speed_choice.hpp"

namespace mg::belief {
namespace {

/// Only the ratio of two launches enters equivalent_club_speed, so its exact value matters little.
constexpr double kLaunchRatio = kNominalLaunchPerClub;

double climb(const field::Field& field, std::array<double, 2> ball, std::array<double, 2> hole) {
  return field.height(hole[0], hole[1]) - field.height(ball[0], ball[1]);
}

}  // namespace

double rolling_deceleration(const field::Field& field) {
  return 5.0 / 7.0 * field.rolling_resistance * kGravity;
}

LaunchGuess prior_launch(const field::Field& field, std::array<double, 2> hole, double arrival) {
  return prior_launch(field, field.tee, hole, arrival);
}

LaunchGuess prior_launch(const field::Field& field, std::array<double, 2> ball,
                         std::array<double, 2> hole, double arrival) {
  const double dx = hole[0] - ball[0], dy = hole[1] - ball[1];
  const double v2 = arrival * arrival + 2.0 * rolling_deceleration(field) * std::hypot(dx, dy) +
                    10.0 / 7.0 * kGravity * climb(field, ball, hole);
  return {std::atan2(dy, dx), 7.0 / 5.0 * std::sqrt(std::max(v2, 0.04))};
}

double prior_arrival(const field::Field& field, std::array<double, 2> ball,
                     std::array<double, 2> hole, double launch_speed) {
  const double roll = 5.0 / 7.0 * launch_speed;
  const double v2 =
      roll * roll -
      2.0 * rolling_deceleration(field) * std::hypot(hole[0] - ball[0], hole[1] - ball[1]) -
      10.0 / 7.0 * kGravity * climb(field, ball, hole);
  return std::sqrt(std::max(v2, 0.0));
}

double equivalent_club_speed(double surveyed_speed, const field::Field& surveyed,
                             const field::Field& believed, double club_speed_scale,
                             std::array<double, 2> ball, std::array<double, 2> hole) {
  const bool alike = surveyed.rolling_resistance == believed.rolling_resistance &&
                     climb(surveyed, ball, hole) == climb(believed, ball, hole);
  if (alike && club_speed_scale == 1.0) return surveyed_speed;
  // The rolling energy the believed green takes beyond the surveyed one over the same distance
  // and climb: the hit keeps its arrival speed (the difference form, exact for Penner's law and
  // free of the prior's absolute calibration, which the slide after the impact blurs).
  const double launch = kLaunchRatio * surveyed_speed;
  const double roll = 5.0 / 7.0 * launch;
  const double distance = std::hypot(hole[0] - ball[0], hole[1] - ball[1]);
  const double extra =
      2.0 * (rolling_deceleration(believed) - rolling_deceleration(surveyed)) * distance +
      10.0 / 7.0 * kGravity * (climb(believed, ball, hole) - climb(surveyed, ball, hole));
  const double wanted = alike ? launch : 7.0 / 5.0 * std::sqrt(std::max(roll * roll + extra, 0.0));
  return surveyed_speed * (wanted / launch) / club_speed_scale;
}

}  // namespace mg::belief
