#pragma once
// Shared by the SEDS tests: target-frame samples of generated demonstrations.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/rng.hpp"
#include "ds/demonstrations.hpp"
#include "ds/seds.hpp"

namespace mg::ds::testing {

// Target-frame samples of generated demonstrations (moving samples only).
inline SedsData demo_data(int count, std::uint64_t seed, double noise_scale = 1.0) {
  DemoGeneratorConfig cfg;
  cfg.count = count;
  cfg.position_noise *= noise_scale;
  cfg.velocity_noise *= noise_scale;
  Rng rng(seed);
  const auto demos = generate_demonstrations(cfg, rng);
  std::vector<Eigen::Vector3d> y, yd;
  for (const auto& d : demos)
    for (std::size_t i = 0; i < d.size(); ++i)
      if (d.xdot[i].norm() > 0.075) {
        y.push_back(d.x[i] - cfg.ball);
        yd.push_back(d.xdot[i]);
      }
  SedsData data;
  data.y.resize(3, static_cast<Eigen::Index>(y.size()));
  data.ydot.resize(3, static_cast<Eigen::Index>(y.size()));
  for (std::size_t i = 0; i < y.size(); ++i) {
    data.y.col(static_cast<Eigen::Index>(i)) = y[i];
    data.ydot.col(static_cast<Eigen::Index>(i)) = yd[i];
  }
  return data;
}

}  // namespace mg::ds::testing
