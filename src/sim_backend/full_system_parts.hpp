#pragma once
/// The parts of a full-system putt (sim_backend/full_system.hpp) other than its flow: the checks of
/// its worlds, the settled ball, the bookkeeping of limits and touches, and the per-thread scratch
/// (PuttScratch's caches). Internal to the simulator backend (not installed).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/rng.hpp"
#include "sim_backend/full_system.hpp"

namespace mg::control {

constexpr double kBallSettleTime = 0.3;  ///< [s] ball at rest in its contact (time constant 0.02 s)
constexpr double kClubReachMargin = 0.05;    ///< [m] tracking error, idle drift
constexpr double kHandoffHysteresis = 0.05;  ///< [m] hand-off this much beyond the fallback radius
constexpr int kMaxHandoffFallbacks = 3;
constexpr std::size_t kSettledCacheSize = 8;
constexpr std::size_t kAtRestCacheSize = 4;

/// After each step: the applied and commanded torque and velocity ratios, the position margin,
/// a fault, and the club-ball touches (from the simulator's contacts).
void track_ratios(const ModuleModel& model, const SimIds& ids, const mjData* d,
                  const ModuleData& data, FullPuttResult& r);

/// The tee (or the stance's ball), plus a Gaussian error of std `placement_noise` per axis (seeded
/// stream 0).
std::array<double, 2> noisy_ball_start(const sim::World& world, const FullPuttOptions& options);

/// The ball world must be the arm world without the arm (InputError otherwise).
void check_ball_world(const sim::World& world, const sim::World& ball);
/// The arm of `world` must stand where `stance` puts the module's mount (InputError otherwise).
void check_stance(const sim::World& world, const ModuleModel& model, const robot::Stance& stance);

/// The ball at `start`, at rest in its ground contact: settled in `settle_world` (the ball world,
/// else `world` with the arm held at the default posture, away from the ball).
sim::BallState settled_ball(const sim::World& settle_world, mjData* sd, const robot::ArmIds* arm,
                            std::array<double, 2> start, std::array<double, 2> hole);

// What of a module model the approach depends on (besides the model's address): its config
// (the rest speeds and the IK options derive from it) and the hitting point x*. A replaced model
// at the same address does not hit the cache.
struct ApproachKey {
  ControllerConfig config;
  Eigen::Vector3d x_star = Eigen::Vector3d::Zero();
  bool operator==(const ApproachKey&) const = default;
};

ApproachKey approach_key(const ModuleModel& model);

struct PuttScratch::Impl {
  // mjData of a ball world; remade when another world is used.
  sim::DataPtr ball_data;
  std::uint64_t ball_data_world = 0;
  // Settled balls: a deterministic function of (settle world, start, hole), so a hit gives the
  // bits of settling anew.
  struct Settled {
    std::uint64_t world = 0;
    std::array<double, 2> start{}, hole{};
    sim::BallState state;
  };
  std::vector<Settled> settled;
  std::size_t next_slot = 0;

  // Arm and ball at the hit request after a simulated approach (RestStart::kApproach), by
  // everything the approach depends on: a hit continues with exactly the bits of the approach.
  struct AtRest {
    std::uint64_t world = 0;
    const ModuleModel* model = nullptr;
    ApproachKey key;
    double angle = 0.0, settle_timeout = 0.0;
    std::array<double, 2> start{}, hole{};
    sim::DataPtr data;
    std::unique_ptr<ModuleData> module;
    long steps = 0;
    FullPuttResult result;  // the bookkeeping of the approach
  };
  std::vector<AtRest> at_rest;
  std::size_t next_at_rest = 0;

  AtRest& at_rest_slot();

  // The simulator's ids of the last arm world (a lookup by name per world, not per putt).
  SimIds ids;
  std::uint64_t ids_world = 0;
  const SimIds& ids_for(const sim::World& w) {
    if (ids_world != w.instance_id()) {
      ids = find_sim_ids(w);
      ids_world = w.instance_id();
    }
    return ids;
  }

  mjData* data_for(const sim::World& w) {
    if (!ball_data || ball_data_world != w.instance_id()) {
      ball_data = w.make_data();
      ball_data_world = w.instance_id();
    }
    return ball_data.get();
  }
  const sim::BallState* find(std::uint64_t w, std::array<double, 2> start,
                             std::array<double, 2> hole) const {
    for (const auto& s : settled)
      if (s.world == w && s.start == start && s.hole == hole) return &s.state;
    return nullptr;
  }
  void store(std::uint64_t w, std::array<double, 2> start, std::array<double, 2> hole,
             const sim::BallState& state) {
    if (settled.size() < kSettledCacheSize) {
      settled.push_back({w, start, hole, state});
    } else {
      settled[next_slot] = {w, start, hole, state};
      next_slot = (next_slot + 1) % kSettledCacheSize;
    }
  }
};

}  // namespace mg::control
