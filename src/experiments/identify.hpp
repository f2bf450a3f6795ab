#pragma once
/// `minigolf identify`'s procedure (docs/belief.md), shared with bench/belief/identify_report:
/// the robot chooses informative putts, plays them with the arm in the true world, perceives the
/// ball paths with the vision's error, and fits its belief: the green from the paths
/// (belief::fit_green), the arm from its club speeds and the launch directions it saw against
/// those its own model predicts for the same hits (belief::fit_arm). The plant builds the true
/// world only: nothing here reads it for the estimate.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "belief/arm_fit.hpp"
#include "belief/belief.hpp"
#include "belief/path_fit.hpp"
#include "control/module_config.hpp"
#include "field/field.hpp"
#include "system/system.hpp"

namespace mg::experiments {

/// One identification putt.
struct IdentifyHit {
  field::Situation situation;  ///< the ball, the hole as seen
  double angle = 0.0;          ///< [rad, world] hitting direction
  double speed = 0.0;          ///< [m/s] club speed commanded
  // What the robot measured in the true world.
  bool hit = false;            ///< the club struck the ball
  double reached_speed = 0.0;  ///< [m/s] the club speed the arm reached (joints)
  belief::ObservedPath path;   ///< the ball path as perceived
};

/// The robot's plan: `putts` hits from the tee (or from balls drawn from `balls`, a region spec
/// as `--balls`; seeded by `seed`), along the lane the longer way (from a ball with a metre of
/// lane both ways, both ways in turn), alternating left and right of
/// its axis, wide (0.5-0.7 rad) and narrow (0.06-0.18 rad), and between a short and a long roll,
/// so that rolling resistance and both slope components separate. Deterministic. Throws
/// InputError.
std::vector<IdentifyHit> plan_identification(const system::System& own, int putts,
                                             const std::string& balls, std::uint64_t seed);

/// Plays `hits` with the arm in `truth`'s world (record interval 0.01 s) and perceives each path
/// with a Gaussian error of `vision_noise` [m] per axis and sample (stream `seed`, per hit);
/// `done(k)` after each (k of them played).
void play_identification(const system::System& truth, std::vector<IdentifyHit>& hits,
                         double vision_noise, std::uint64_t seed,
                         const std::function<void(int)>& done = {});

/// What the robot measured of `hit` played with `result`: whether the club struck, the club speed
/// its joints reached, and the ball path (samples at least `interval` [s] apart, from the first)
/// with a Gaussian error of `vision_noise` [m] per axis and sample (stream `seed`).
void perceive_hit(IdentifyHit& hit, const control::FullPuttResult& result, double vision_noise,
                  std::uint64_t seed, double interval = 0.0);

/// A belief identified from hits.
struct Identification {
  belief::Belief belief;
  belief::GreenEstimate green;
  belief::ArmEstimate arm;                           ///< the hits' own fit (before any prior)
  std::vector<belief::ArmObservation> observations;  ///< one per hit used
  double fit_cpu = 0.0;                              ///< [s] CPU of the fits (fit_green, fit_arm)
  double predict_cpu = 0.0;  ///< [s] CPU of the robot's model hits (the arm's predictions)
};

/// The green prior of `prior` over `surveyed` (a key without a std: the survey's spread, rho
/// 25 %, slopes 0.01); without a prior the survey with that spread.
belief::GreenPrior green_prior(const field::Field& surveyed,
                               const std::optional<belief::Belief>& prior);

/// Fits the belief from the first `n` of `hits` (played): the green (MAP with green_prior), then
/// the arm, predicting each hit in the robot's own model (`config`'s arm and hitting model on
/// the believed lane, no plant). Arm keys of `prior` with a std are combined with the fit
/// (inverse variances); the hole offset and sliding friction are the prior's (not identified
/// from paths); the vision's noise is the green fit's rms residual. `every_run`: the green from
/// every rolling run of each path (belief::rolling_spans: putts over crests), else from its
/// first. Throws NumericalError when no path rolls long enough.
Identification identify_belief(const control::ModuleConfig& config, const field::Field& surveyed,
                               const std::vector<IdentifyHit>& hits, std::size_t n,
                               const std::optional<belief::Belief>& prior, bool every_run = false);

/// The whole procedure on `truth` (the world the putts happen in, built from `config`; its
/// field() is what the robot believes before): plan `putts` hits, play them with the arm,
/// perceive them with the truth's vision noise, and fit the belief with `prior`. Seeded by `seed`;
/// `done(k)` after each putt. Throws as its parts.
Identification identify_world(const control::ModuleConfig& config, const system::System& truth,
                              int putts, const std::string& balls, std::uint64_t seed,
                              const std::optional<belief::Belief>& prior,
                              const std::function<void(int)>& done = {});

/// [s] The window of the launch direction (belief::path_direction) in a path: from 30 ms after
/// the launch to 0.5 s, or to the first sample near a border, an obstacle or the hole.
std::array<double, 2> launch_window(const field::Field& field, const belief::ObservedPath& path);

}  // namespace mg::experiments
