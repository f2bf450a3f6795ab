#pragma once
/// The launch-error study (thesis 6.1, figure 6.1): the arm hits the ball `hits` times at each
/// commanded hitting angle with execution noise (FullPuttOptions::torque_noise, placement_noise)
/// and the ball's launch angle is compared with the command. Also the hitting-speed error: the
/// club speed at impact vs the commanded speed, and the ball's launch speed / club speed.
///
/// Hit i at angle index a uses the noise seed derive_seed(derive_seed(seed, a), i): results do
/// not depend on the order in which hits are run. Deterministic: same inputs, same bits.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim_backend/full_system.hpp"
#include "system/system.hpp"

namespace mg::experiments {

struct LaunchStudyOptions {
  std::vector<double> angles_deg{-10.0, 0.0, 10.0};  ///< commanded hitting angles [deg]
  int hits = 10;                                     ///< hits per angle
  double speed = 1.0;                                ///< commanded club speed [m/s]
  double torque_noise = 0.01;      ///< joint-torque disturbance std / torque limit [-]
  double placement_noise = 0.001;  ///< ball placement std per axis [m]
  std::uint64_t seed = 1;
  std::array<double, 2> hole{2.0, 0.0};  ///< only the launch matters
  control::FullPuttOptions putt{};  ///< timeouts etc.; its noise fields and seed are set per hit
  /// Validates the options; throws InputError naming the bad one.
  void validate() const;
};

/// One hit. Angles in radians unless named _deg.
struct LaunchHit {
  int angle_index = 0;
  int hit_index = 0;
  double commanded_angle_deg = 0.0;
  double commanded_speed = 0.0;  ///< [m/s]
  std::uint64_t seed = 0;        ///< the putt's noise seed
  bool hit = false;              ///< the club struck the ball (else the numbers below are NaN)
  std::array<double, 2> ball_start{0.0, 0.0};  ///< [m]
  double club_angle = 0.0;                     ///< [rad] face velocity direction at contact
  double club_speed = 0.0;                     ///< [m/s] face speed at contact
  double launch_angle = 0.0;                   ///< [rad] ball launch direction
  double launch_speed = 0.0;                   ///< [m/s] ball launch speed (horizontal)
  double launch_error_deg = 0.0;               ///< launch angle - commanded angle [deg]
  double club_speed_error = 0.0;               ///< club speed - commanded speed [m/s]
  double launch_club_ratio = 0.0;              ///< launch speed / club speed [-]
  bool faulted = false;                        ///< a module fault was observed during the run
  double rest_time = 0.0;                      ///< [s] simulated time to reach the rest pose
  /// Why the club did not strike the ball: "" (it did), "refused", "not at rest" (rest pose not
  /// reached within the settle timeout), "fault", "no contact".
  std::string failure;
};

/// Per commanded angle, over the hits that struck the ball. Std: sample std (n - 1; 0 for n < 2).
struct LaunchAngleSummary {
  double commanded_angle_deg = 0.0;
  int n = 0;       ///< hits that struck the ball
  int missed = 0;  ///< hits that did not (refused, no contact)
  double mean_error_deg = 0.0;
  double std_error_deg = 0.0;
  double mean_club_speed_error = 0.0;      ///< [m/s]
  double std_club_speed_error = 0.0;       ///< [m/s]
  double mean_club_speed_error_pct = 0.0;  ///< 100 * mean club speed error / commanded speed
  double mean_launch_club_ratio = 0.0;
  double std_launch_club_ratio = 0.0;
};

struct LaunchStudyResult {
  LaunchStudyOptions options;
  std::string field;
  std::vector<LaunchHit> hits;              ///< angle-major, hit-minor
  std::vector<LaunchAngleSummary> summary;  ///< one per angle, in the options' order
};

/// Runs the study on the system's arm, on `threads` threads (0: all cores; the hits are the same
/// bits for any count: each has its own seed). `progress` (optional) is called after every hit,
/// in completion order. Throws InputError for bad options.
LaunchStudyResult run_launch_study(const system::System& system, const LaunchStudyOptions& options,
                                   int threads = 0,
                                   const std::function<void(const LaunchHit&)>& progress = {});

/// The per-angle summaries from hits (exposed for tests).
std::vector<LaunchAngleSummary> summarize_launch_hits(const std::vector<double>& angles_deg,
                                                      double speed,
                                                      const std::vector<LaunchHit>& hits);

/// CSV, one row per hit: angle_deg,hit,seed,struck,ball_x,ball_y,club_angle,club_speed,
/// launch_angle,launch_speed,launch_error_deg,club_speed_error,launch_club_ratio,faulted
/// (numbers in shortest round-trip form).
std::string launch_study_csv(const LaunchStudyResult& result);

/// Markdown: a one-line description of the run, then the table (one row per angle).
std::string launch_study_markdown(const LaunchStudyResult& result);

}  // namespace mg::experiments
