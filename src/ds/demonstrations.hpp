#pragma once
/// Hitting demonstrations: recorded club-head trajectories {t, x, xdot} that end at the ball.
///
/// CSV format (`data/demos/*.csv`): header `demo,t,x,y,z,vx,vy,vz`; one row per sample; `demo` is
/// an integer id (rows of one demonstration are contiguous, time strictly increasing); metres,
/// seconds, metres per second; world frame (ball/tee at (0, 0, 0.02135), +x the default hitting
/// direction psi0, z up).
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "core/csv.hpp"
#include "core/rng.hpp"

namespace mg::ds {

/// Radius of a golf ball [m]; the ball centre on the tee is at height kBallRadius.
inline constexpr double kBallRadius = 0.02135;

/// One recorded hitting motion.
struct Demonstration {
  int id = 0;
  std::vector<double> t;              ///< [s], strictly increasing
  std::vector<Eigen::Vector3d> x;     ///< club-head position [m], world frame
  std::vector<Eigen::Vector3d> xdot;  ///< club-head velocity [m/s], world frame
  std::size_t size() const { return t.size(); }
};

/// Settings of the synthetic "human-like" demonstration generator (defaults in one place).
///
/// Each demonstration starts at rest at a random point behind, above and beside the ball and
/// follows a quintic Bezier path whose last three control points lie on the hitting line, so the
/// final approach is straight along psi0 with zero curvature at the ball. Speed along the path is
/// a bell `v_peak sin^2(pi tau / (2 tau_peak))` of normalised time `tau`, peaking at `tau_peak`
/// just before the ball so the speed stays high at impact (v(1) = hitting speed).
struct DemoGeneratorConfig {
  int count = 8;                                ///< number of demonstrations
  Eigen::Vector3d ball{0.0, 0.0, kBallRadius};  ///< hitting point x* [m], world
  double behind_min = 0.25, behind_max = 0.45;  ///< start distance behind the ball along -x [m]
  double above_min = 0.05, above_max = 0.20;    ///< start height above the ball [m]
  double side_min = -0.06, side_max = 0.12;     ///< start offset along y [m]
  double hitting_speed = 1.5;                   ///< common speed at the ball [m/s]
  double hitting_speed_jitter = 0.02;           ///< relative spread of the hitting speed (1 sigma)
  double tau_peak = 0.9;                        ///< where the bell peaks, fraction of duration
  double straight_length = 0.06;                ///< Bezier control-point spacing on the line [m]
  double sample_period = 0.01;                  ///< [s] (100 Hz, a typical tracker rate)
  double position_noise = 3e-4;                 ///< [m], 1 sigma, i.i.d. per axis
  double velocity_noise = 0.01;                 ///< [m/s], 1 sigma, i.i.d. per axis
  void validate() const;                        ///< throws InputError naming the field
};

/// Generates `config.count` demonstrations; deterministic in the state of `rng`.
std::vector<Demonstration> generate_demonstrations(const DemoGeneratorConfig& config, Rng& rng);

/// Converts a parsed CSV table (see file format above) to demonstrations; throws InputError on
/// a missing column, a non-integer or non-contiguous demo id, non-increasing time or a
/// demonstration with fewer than `min_samples` samples.
std::vector<Demonstration> demonstrations_from_table(const CsvTable& table,
                                                     std::size_t min_samples = 2);

/// Reads a demonstrations CSV file (IoError if unreadable, InputError if malformed).
std::vector<Demonstration> read_demonstrations(const std::filesystem::path& path);

/// CSV text of demonstrations, numbers in round-trip form.
std::string format_demonstrations(const std::vector<Demonstration>& demos);

/// Summary used by the fit: the common end point and approach direction of the demonstrations.
struct DemoSummary {
  Eigen::Vector3d x_star;    ///< mean end point [m], world
  Eigen::Vector3d psi0;      ///< unit horizontal mean final direction, world
  double end_spread = 0.0;   ///< largest distance of an end point from x_star [m]
  double hitting_speed = 0;  ///< mean final speed [m/s]
};

/// Checks that the demonstrations are usable for a hitting model and summarises them: at least
/// one demonstration, each with >= 3 samples, finite values, end points within `end_tolerance`
/// of their mean, a non-zero final speed with a mostly horizontal direction, and final
/// directions within 30 degrees of each other. Throws InputError with the reason.
DemoSummary summarize_demonstrations(const std::vector<Demonstration>& demos,
                                     double end_tolerance = 0.02);

}  // namespace mg::ds
