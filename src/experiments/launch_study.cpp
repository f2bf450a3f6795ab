#include "experiments/launch_study.hpp"

#include "experiments/wire.hpp"
#include "system/distributed.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"
#include "core/rng.hpp"

namespace mg::experiments {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Welford: identical samples give exactly their value as mean and exactly 0 as std.
struct RunningStats {
  int n = 0;
  double mean = 0.0;
  double m2 = 0.0;
  void add(double x) {
    ++n;
    const double delta = x - mean;
    mean += delta / n;
    m2 += delta * (x - mean);
  }
  double sample_std() const { return n < 2 ? 0.0 : std::sqrt(m2 / (n - 1)); }
};

}  // namespace

void LaunchStudyOptions::validate() const {
  if (angles_deg.empty()) throw InputError("launch study: angles: expected at least one angle");
  for (double a : angles_deg)
    if (!std::isfinite(a))
      throw InputError(fmt::format("launch study: angles: expected finite degrees, got {}", a));
  if (hits < 1 || hits > 100000)
    throw InputError(fmt::format("launch study: hits: expected 1..100000 per angle, got {}", hits));
  if (!std::isfinite(speed) || speed <= 0.0)
    throw InputError(fmt::format("launch study: speed: expected > 0 m/s, got {}", speed));
  if (!std::isfinite(torque_noise) || torque_noise < 0.0 || torque_noise > 1.0)
    throw InputError(fmt::format(
        "launch study: torque noise: expected 0..1 (fraction of the torque limit), got {}",
        torque_noise));
  if (!std::isfinite(placement_noise) || placement_noise < 0.0 || placement_noise > 0.05)
    throw InputError(
        fmt::format("launch study: placement noise: expected 0..0.05 m, got {}", placement_noise));
}

std::vector<LaunchAngleSummary> summarize_launch_hits(const std::vector<double>& angles_deg,
                                                      double speed,
                                                      const std::vector<LaunchHit>& hits) {
  std::vector<LaunchAngleSummary> out;
  out.reserve(angles_deg.size());
  for (std::size_t a = 0; a < angles_deg.size(); ++a) {
    LaunchAngleSummary s;
    s.commanded_angle_deg = angles_deg[a];
    RunningStats err, club, ratio;
    for (const LaunchHit& h : hits) {
      if (h.angle_index != static_cast<int>(a)) continue;
      if (!h.hit) {
        ++s.missed;
        continue;
      }
      err.add(h.launch_error_deg);
      club.add(h.club_speed_error);
      ratio.add(h.launch_club_ratio);
    }
    s.n = err.n;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.mean_error_deg = s.n > 0 ? err.mean : nan;
    s.std_error_deg = s.n > 0 ? err.sample_std() : nan;
    s.mean_club_speed_error = s.n > 0 ? club.mean : nan;
    s.std_club_speed_error = s.n > 0 ? club.sample_std() : nan;
    s.mean_club_speed_error_pct = s.n > 0 ? 100.0 * club.mean / speed : nan;
    s.mean_launch_club_ratio = s.n > 0 ? ratio.mean : nan;
    s.std_launch_club_ratio = s.n > 0 ? ratio.sample_std() : nan;
    out.push_back(s);
  }
  return out;
}

LaunchStudyResult run_launch_study(const system::System& system, const LaunchStudyOptions& options,
                                   int threads,
                                   const std::function<void(const LaunchHit&)>& progress) {
  options.validate();
  LaunchStudyResult result;
  result.options = options;
  result.field = system.field().name;
  const int n_angles = static_cast<int>(options.angles_deg.size());
  result.hits.resize(static_cast<std::size_t>(n_angles * options.hits));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto job = [&](int index, system::SystemData& data) {
    const auto a = static_cast<std::size_t>(index / options.hits);
    const int i = index % options.hits;
    const std::uint64_t angle_seed = derive_seed(options.seed, a);
    const double angle = options.angles_deg[a] * kDeg;
    control::FullPuttOptions putt = options.putt;
    putt.placement_noise = options.placement_noise;
    putt.seed = derive_seed(angle_seed, static_cast<std::uint64_t>(i));
    // The execution noise: a wrapper of the simulated arm, drawn from the putt's seed.
    control::PlantEffectValues noise;
    noise.torque_noise = options.torque_noise;
    const control::FullPuttResult r =
        system::arm_putt(system, data, options.hole, angle, options.speed, putt, noise);
    LaunchHit& h = result.hits[static_cast<std::size_t>(index)];
    h.angle_index = static_cast<int>(a);
    h.hit_index = i;
    h.commanded_angle_deg = options.angles_deg[a];
    h.commanded_speed = options.speed;
    h.seed = putt.seed;
    h.hit = r.hit;
    h.ball_start = r.ball_start;
    h.faulted = r.faulted;
    h.rest_time = r.rest_time;
    if (!r.hit)
      h.failure = r.hit_refused                               ? "refused"
                  : r.rest_time >= putt.settle_timeout - 1e-9 ? "not at rest"
                  : r.faulted                                 ? "fault"
                                                              : "no contact";
    if (r.hit) {
      h.club_angle = r.club.angle;
      h.club_speed = r.club.speed;
      h.launch_angle = r.launch.angle;
      h.launch_speed = r.launch.speed;
      h.launch_error_deg = (r.launch.angle - angle) / kDeg;
      h.club_speed_error = r.club.speed - options.speed;
      h.launch_club_ratio = r.club.speed > 0.0 ? r.launch.speed / r.club.speed : nan;
    } else {
      h.club_angle = h.club_speed = h.launch_angle = h.launch_speed = nan;
      h.launch_error_deg = h.club_speed_error = h.launch_club_ratio = nan;
    }
  };
  system::distributed_for(system, result.hits, threads, job, [&](int index) {
    if (progress) progress(result.hits[static_cast<std::size_t>(index)]);
  });
  result.summary = summarize_launch_hits(options.angles_deg, options.speed, result.hits);
  return result;
}

std::string launch_study_csv(const LaunchStudyResult& result) {
  std::string out =
      "angle_deg,hit,seed,struck,ball_x,ball_y,club_angle,club_speed,launch_angle,launch_speed,"
      "launch_error_deg,club_speed_error,launch_club_ratio,faulted\n";
  for (const LaunchHit& h : result.hits) {
    out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                       format_exact(h.commanded_angle_deg), h.hit_index, h.seed, h.hit ? 1 : 0,
                       format_exact(h.ball_start[0]), format_exact(h.ball_start[1]),
                       format_exact(h.club_angle), format_exact(h.club_speed),
                       format_exact(h.launch_angle), format_exact(h.launch_speed),
                       format_exact(h.launch_error_deg), format_exact(h.club_speed_error),
                       format_exact(h.launch_club_ratio), h.faulted ? 1 : 0);
  }
  return out;
}

std::string launch_study_markdown(const LaunchStudyResult& result) {
  const LaunchStudyOptions& o = result.options;
  std::string out = fmt::format(
      "Launch-angle error (thesis 6.1) on {}: {} hits per angle, club speed {} m/s, torque noise "
      "{} x limit, placement noise {} m, seed {}.\n\n",
      result.field, o.hits, o.speed, o.torque_noise, o.placement_noise, o.seed);
  out +=
      "| angle [deg] | n | mean error [deg] | std [deg] | club speed error mean [m/s] | "
      "club speed error std [m/s] | club speed error [%] | launch/club mean | launch/club std |\n"
      "|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const LaunchAngleSummary& s : result.summary) {
    out += fmt::format(
        "| {:g} | {}{} | {:+.3f} | {:.3f} | {:+.4f} | {:.4f} | {:+.2f} | {:.4f} | {:.4f} |\n",
        s.commanded_angle_deg, s.n,
        s.missed > 0 ? fmt::format(" ({} missed)", s.missed) : std::string(), s.mean_error_deg,
        s.std_error_deg, s.mean_club_speed_error, s.std_club_speed_error,
        s.mean_club_speed_error_pct, s.mean_launch_club_ratio, s.std_launch_club_ratio);
  }
  return out;
}

}  // namespace mg::experiments
