#include "selfteach/crkr.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "system/observe.hpp"
#include "teacher/teacher.hpp"

namespace mg::selfteach {

void CrkrOptions::validate() const {
  if (budget < 1 || budget > 100000)
    throw InputError(fmt::format("crkr: budget: expected 1..100000 putts, got {}", budget));
  if (!(lambda > 0.0 && lambda < 1e6))
    throw InputError(fmt::format("crkr: lambda: expected > 0, got {}", lambda));
  if (!(bandwidth >= 0.0 && bandwidth < 10.0))
    throw InputError(fmt::format("crkr: bandwidth: expected 0..10 m, got {}", bandwidth));
  if (!(sigma_angle > 0.0 && sigma_angle < 1.0 && sigma_speed > 0.0 && sigma_speed < 2.0))
    throw InputError(
        "crkr: exploration scales: expected 0 < sigma_angle < 1 rad, 0 < sigma_speed < 2 m/s");
}

std::array<double, 3> CrkrPolicy::act(const field::Field& field, const field::Situations& region,
                                      std::array<double, 2> hole) const {
  auto a = prior_club(field, region, {field.tee, hole}, arrival, bias, ratio);
  const auto n = static_cast<Eigen::Index>(holes.size());
  if (n == 0) return {a[0], a[1], std::sqrt(1.0 + lambda)};
  const auto kernel = [&](std::array<double, 2> p, std::array<double, 2> q) {
    const double d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]);
    return std::exp(-0.5 * d2 / (bandwidth * bandwidth));
  };
  Eigen::MatrixXd k(n, n);
  Eigen::VectorXd ks(n);
  Eigen::MatrixXd r(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    for (Eigen::Index j = 0; j < n; ++j)
      k(i, j) = kernel(holes[ui], holes[static_cast<std::size_t>(j)]);
    k(i, i) += lambda * costs[ui];
    ks(i) = kernel(hole, holes[ui]);
    r(i, 0) = residuals[ui][0];
    r(i, 1) = residuals[ui][1];
  }
  const Eigen::LDLT<Eigen::MatrixXd> f(k);
  const Eigen::VectorXd w = f.solve(ks);
  a[0] += w.dot(r.col(0));
  if (region.learn_speed) a[1] += w.dot(r.col(1));
  const double var = std::max(0.0, 1.0 + lambda - ks.dot(w));
  return {a[0], a[1], std::sqrt(var)};
}

CrkrResult crkr_learn(const system::System& system, const field::Situations& region,
                      const CrkrOptions& options) {
  options.validate();
  region.validate(system.field(), "crkr region");
  if (region.balls)
    throw InputError("crkr: plays from the tee; this region has a ball region (not supported)");
  const auto& field = system.field();
  const auto& cfg = system.config();
  CrkrResult res;
  CrkrPolicy& pol = res.policy;
  pol.lambda = options.lambda;
  const auto b = region_bounds(region);
  pol.bandwidth = options.bandwidth > 0.0
                      ? options.bandwidth
                      : std::max(0.02, 0.25 * std::max(b[1] - b[0], b[3] - b[2]));
  pol.arrival = teacher::arrival_speed(field, teacher::parse_strategy(region.strategy));
  std::vector<int> checkpoints = options.checkpoints;
  std::sort(checkpoints.begin(), checkpoints.end());
  std::size_t next = 0;
  system::SystemData data(system);
  Rng rng(derive_seed(options.seed, 21));
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int e = 0; e < options.budget; ++e) {
    const auto hole = region.sample(rng);
    const auto act = pol.act(field, region, hole);
    double angle = act[0] + act[2] * options.sigma_angle * normal(rng);
    double speed = act[1];
    const double speed_draw =
        normal(rng);  // drawn always: the stream does not depend on the region
    if (region.learn_speed) speed += act[2] * options.sigma_speed * speed_draw;
    angle = std::clamp(angle, cfg.angle_min + 1e-6, cfg.angle_max - 1e-6);
    speed = std::clamp(speed, cfg.speed_min, cfg.speed_max);
    control::FullPuttOptions o;  // cameras of its own read the launch from a recorded path
    if (system::paths_seen_by_perception(system)) o.record_interval = 0.01;
    auto r = system::arm_putt(system, data, hole, angle, speed, o);
    system::perceive_putt(system, data, r);
    const PuttRecord p = record_putt({field.tee, hole}, angle, speed, r);
    res.sunk += p.sunk;
    res.putts.push_back(p);
    // The residuals are re-expressed against the prior with the launch relation as now measured.
    const auto relation = launch_relation(res.putts);
    pol.bias = relation[0];
    pol.ratio = relation[1];
    double cost = 0.02;
    if (!p.sunk) {
      cost += std::min(p.closest_approach, 1.0) / 0.05;
      if (region.learn_speed) cost += std::abs(p.approach_speed - pol.arrival) / 0.5;
    }
    pol.holes.push_back(hole);
    pol.costs.push_back(cost);
    pol.residuals.clear();
    for (const auto& q : res.putts) {
      const auto prior =
          prior_club(field, region, {field.tee, q.target}, pol.arrival, pol.bias, pol.ratio);
      pol.residuals.push_back({q.angle - prior[0], q.speed - prior[1]});
    }
    while (next < checkpoints.size() && checkpoints[next] <= e + 1)
      res.checkpoint_policies.emplace_back(checkpoints[next++], pol);
  }
  return res;
}

}  // namespace mg::selfteach
