#pragma once
/// Noise-aware putting (docs/selfteach.md): choose the putt that maximises the probability of
/// sinking under the measured noise rather than the mean prediction.
///
/// The choice the self-teacher can make is the arrival speed s* it learns to reach the hole with
/// (the aim stays at the hole's centre: the noise is symmetric about it). A fast arrival survives
/// a short launch or a hole farther than seen; a slow one is captured over more of the cup's width.
/// With the noise as the robot measures it —
///   launch angle std sigma_theta [rad] and relative launch speed std sigma_u (practice putts at
///   one club setting under the execution noise), the perceived hole's std sigma_p [m] per axis —
/// a putt aimed at a hole at distance D arriving at s gives, to first order,
///   lateral offset  b = D dtheta + e_lat,     arrival  s_h^2 = s^2 + 2 (5/7 u)^2 du/u + 2 a
///   e_along
/// (u the launch speed, a the rolling deceleration, e the hole's position error), and sinks when
/// the ball reaches the cup (s_h^2 > -2 a (R - r)) slower than the capture speed at its offset,
///   v_c(b) = v_c0 sqrt(1 - (b / R)^2),  v_c0 = 1.69 m/s (the measured centred lip-out of the
///   108 mm, 60 mm deep cup, docs/physics.md) scaled by the cup's depth as teacher::arrival_speed.
/// P(sink | s) is estimated by Monte Carlo (fixed draws, so the choice is deterministic) and
/// maximised over a grid of s.
#include <array>
#include <cstdint>
#include <vector>

#include "field/situations.hpp"
#include "system/system.hpp"

namespace mg::selfteach {

struct LaunchNoise {
  double angle_std = 0.0;      ///< [rad] launch angle
  double speed_rel_std = 0.0;  ///< launch speed std / mean
  double position_std = 0.0;   ///< [m] perceived hole position error per axis (xi: hole and ball)
  int putts = 0;               ///< practice putts the measurement cost
};

/// Measures the launch scatter under `torque_noise` with `putts` practice putts (>= 2) at the
/// region's centre (club speed from the prior); `position_std` is passed through.
LaunchNoise measure_launch_noise(const system::System& system, const field::Situations& region,
                                 double torque_noise, double position_std, int putts,
                                 std::uint64_t seed);

/// P(sink) of arriving at `arrival` [m/s] at a hole `distance` [m] away under `noise`.
double sink_probability(const field::Field& field, double distance, double arrival,
                        const LaunchNoise& noise, int draws = 4000, std::uint64_t seed = 1);

/// The arrival speed in [0.2, 1.2] m/s (steps of 0.05) maximising sink_probability at the
/// region's mean distance; the smallest on ties.
double robust_arrival_speed(const field::Field& field, const field::Situations& region,
                            const LaunchNoise& noise);

}  // namespace mg::selfteach
