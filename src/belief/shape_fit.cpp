#include "belief/shape_fit.hpp"

#include <cmath>
#include <cstdio>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "core/error.hpp"
#include "plant/plant.hpp"

namespace mg::belief {
namespace {

/// [m] the height step of the heights' difference quotients.
constexpr double kHeightStep = 1e-4;

void check_options(const ShapeOptions& o) {
  const auto check = [](const char* key, double v, double lo, double hi) {
    if (!(v >= lo && v <= hi))
      throw InputError(fmt::format("fit_shape: {}: expected {}..{}, got {}", key, lo, hi, v));
  };
  check("spacing", o.spacing, 0.05, 2.0);
  check("sigma_ratio", o.sigma_ratio, 0.2, 3.0);
  check("height_std", o.height_std, 1e-6, 0.05);
  check("rounds", o.rounds, 1, 10);
}

/// The grid of `spacing` over the lane's bounds whose bumps lie within 1.5 widths of a fitted
/// sample.
std::vector<field::BumpTerm> crossed_grid(const field::Field& lane, const GreenEstimate& green,
                                          const std::vector<ObservedPath>& paths, double spacing,
                                          double sigma) {
  const auto& b = lane.bounds;
  const int nx = static_cast<int>(std::floor((b[1] - b[0]) / spacing)) + 1;
  const int ny = static_cast<int>(std::floor((b[3] - b[2]) / spacing)) + 1;
  const double x0 = 0.5 * (b[0] + b[1] - (nx - 1) * spacing);
  const double y0 = 0.5 * (b[2] + b[3] - (ny - 1) * spacing);
  const double reach2 = 2.25 * sigma * sigma;
  std::vector<field::BumpTerm> grid;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double cx = x0 + i * spacing, cy = y0 + j * spacing;
      bool crossed = false;
      for (std::size_t k = 0; k < paths.size() && !crossed; ++k) {
        const PathFit& pf = green.paths[k];
        if (!pf.used) continue;
        for (std::size_t s = pf.first; s < pf.last && !crossed; ++s) {
          const double dx = paths[k].samples[s][1] - cx, dy = paths[k].samples[s][2] - cy;
          crossed = dx * dx + dy * dy < reach2;
        }
      }
      if (!crossed) continue;
      field::BumpTerm t;
      t.center = {cx, cy};
      t.height = 0.0;
      t.sigma = {sigma, sigma};
      grid.push_back(t);
    }
  return grid;
}

/// The fitted samples' model positions on `lane` with the green and starts of `green`, stacked
/// (x, y) path after path.
Eigen::VectorXd model_positions(const field::Field& lane, const GreenEstimate& green,
                                const std::vector<ObservedPath>& paths) {
  std::vector<double> out;
  const GreenParams params{green.rolling_resistance, green.extra_slope};
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const PathFit& pf = green.paths[k];
    if (!pf.used) continue;
    std::vector<double> times;
    for (std::size_t s = pf.first; s < pf.last; ++s) times.push_back(paths[k].samples[s][0]);
    for (const auto& xy : predict_roll(lane, params, pf.start, times)) {
      out.push_back(xy[0]);
      out.push_back(xy[1]);
    }
  }
  return Eigen::Map<Eigen::VectorXd>(out.data(), static_cast<Eigen::Index>(out.size()));
}

}  // namespace

field::Field with_bumps(const field::Field& surveyed, const std::vector<field::BumpTerm>& bumps) {
  field::Field lane = surveyed;
  for (const auto& b : bumps) lane.surface.terms.emplace_back(b);
  return lane;
}

ShapeEstimate fit_shape(const field::Field& surveyed, const std::vector<ObservedPath>& paths,
                        const GreenPrior& prior, const ShapeOptions& options) {
  check_options(options);
  ShapeEstimate out;
  out.green = fit_green(surveyed, paths, prior, 0.0);
  out.rms_before = out.green.rms_residual;
  std::vector<field::BumpTerm> grid;
  for (double spacing = options.spacing;; spacing *= 1.25) {
    grid = crossed_grid(surveyed, out.green, paths, spacing, options.sigma_ratio * spacing);
    if (grid.size() <= plant::kMaxPlantBumps) break;
  }
  if (grid.empty()) return out;
  const auto k = static_cast<Eigen::Index>(grid.size());
  for (int round = 0; round < options.rounds; ++round) {
    const field::Field lane = with_bumps(surveyed, grid);
    if (round > 0) out.green = fit_green(lane, paths, prior, 0.0);
    Eigen::VectorXd observed;
    {
      std::vector<double> obs;
      for (std::size_t p = 0; p < paths.size(); ++p) {
        const PathFit& pf = out.green.paths[p];
        if (!pf.used) continue;
        for (std::size_t s = pf.first; s < pf.last; ++s) {
          obs.push_back(paths[p].samples[s][1]);
          obs.push_back(paths[p].samples[s][2]);
        }
      }
      observed = Eigen::Map<Eigen::VectorXd>(obs.data(), static_cast<Eigen::Index>(obs.size()));
    }
    const Eigen::VectorXd base = model_positions(lane, out.green, paths);
    Eigen::MatrixXd jac(base.size(), k);
    for (Eigen::Index j = 0; j < k; ++j) {
      std::vector<field::BumpTerm> bumped = grid;
      bumped[static_cast<std::size_t>(j)].height += kHeightStep;
      jac.col(j) = (model_positions(with_bumps(surveyed, bumped), out.green, paths) - base) /
                   kHeightStep;
    }
    // MAP step on the heights: the data at the green fit's residual, each height ~ N(0, std).
    const double sigma2 = std::max(out.green.rms_residual * out.green.rms_residual, 1e-12);
    const double lambda = sigma2 / (options.height_std * options.height_std);
    Eigen::VectorXd h(k);
    for (Eigen::Index j = 0; j < k; ++j) h(j) = grid[static_cast<std::size_t>(j)].height;
    Eigen::MatrixXd normal = jac.transpose() * jac + lambda * Eigen::MatrixXd::Identity(k, k);
    Eigen::VectorXd rhs = jac.transpose() * (observed - base) - lambda * h;
    // The heights' plane (their least-squares tilt over the grid) is the tilt's and, along the
    // paths, the rolling resistance's: a ramp slows a ball as grass does. Pinned at 0 with a
    // weight far above the data's, so the bumps hold only what one rho and one tilt cannot.
    const double pin = 1e3 * std::max(jac.squaredNorm() / static_cast<double>(k), lambda);
    for (int axis = 0; axis < 2; ++axis) {
      Eigen::VectorXd g(k);
      for (Eigen::Index j = 0; j < k; ++j) g(j) = grid[static_cast<std::size_t>(j)].center[axis];
      g.array() -= g.mean();
      if (g.norm() == 0.0) continue;
      g /= g.norm();
      normal += pin * g * g.transpose();
      rhs -= pin * g * g.dot(h);
    }
    const Eigen::VectorXd step = normal.ldlt().solve(rhs);
    if (!step.allFinite()) throw NumericalError("fit_shape: the heights' step is not finite");

    for (Eigen::Index j = 0; j < k; ++j)
      grid[static_cast<std::size_t>(j)].height =
          std::clamp(h(j) + step(j), -0.05, 0.05);  // the plant file's range
  }
  out.green = fit_green(with_bumps(surveyed, grid), paths, prior, 0.0);
  out.bumps = std::move(grid);
  return out;
}

}  // namespace mg::belief
