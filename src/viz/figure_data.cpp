#include "viz/figure_data.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "ds/hitting_ds.hpp"

namespace mg::viz {

DsPlane parse_ds_plane(const std::string& name) {
  if (name == "xz") return DsPlane::kXz;
  if (name == "xy") return DsPlane::kXy;
  throw InputError(fmt::format("--plane '{}': expected xz or xy", name));
}

namespace {

ds::HittingDsData default_command(const ds::HittingModel& model) {
  ds::HittingDsData data(model);
  ds::HittingCommand c;
  c.angle = 0.0;
  c.speed = model.default_speed();
  c.modulator = ds::Modulator::kConstant;
  c.start = model.x_star() - 0.3 * model.psi0();
  data.set_command(model, c);
  return data;
}

double mean_start_distance(const ds::HittingModel& model,
                           const std::vector<ds::Demonstration>& demos) {
  double sum = 0.0;
  for (const auto& d : demos) sum += (d.x.front() - model.x_star()).norm();
  return demos.empty() ? 0.3 : sum / static_cast<double>(demos.size());
}

}  // namespace

std::string demonstrations_csv(const std::vector<ds::Demonstration>& demos,
                               const ds::HittingModel& model) {
  std::vector<std::vector<double>> rows;
  for (const auto& d : demos)
    for (std::size_t i = 0; i < d.size(); ++i)
      rows.push_back({static_cast<double>(d.id), d.t[i], d.x[i].x(), d.x[i].y(), d.x[i].z(),
                      d.xdot[i].norm(), (d.x[i] - model.x_star()).norm()});
  return format_csv({"demo", "t", "x", "y", "z", "speed", "distance"}, rows);
}

std::string gmm_csv(const ds::HittingModel& model) {
  const stats::Gmm& g = model.seds_gmm();
  std::vector<std::vector<double>> rows;
  for (int k = 0; k < g.num_components(); ++k) {
    const Eigen::VectorXd& m = g.means[static_cast<std::size_t>(k)];
    const Eigen::MatrixXd& c = g.covariances[static_cast<std::size_t>(k)];
    const Eigen::Vector3d w = m.head<3>() + model.x_star();
    rows.push_back({static_cast<double>(k), g.priors[k], w.x(), w.y(), w.z(), c(0, 0), c(0, 1),
                    c(0, 2), c(1, 1), c(1, 2), c(2, 2)});
  }
  return format_csv({"k", "prior", "mx", "my", "mz", "cxx", "cxy", "cxz", "cyy", "cyz", "czz"},
                    rows);
}

std::string ds_field_csv(const ds::HittingModel& model, const std::vector<ds::Demonstration>& demos,
                         DsPlane plane, int n) {
  if (n < 2 || n > 400)
    throw InputError(fmt::format("ds field: grid of {} points: expected 2..400", n));
  const int ia = 0, ib = plane == DsPlane::kXz ? 2 : 1;
  const Eigen::Vector3d& xs = model.x_star();
  double a0 = xs[ia], a1 = xs[ia], b0 = xs[ib], b1 = xs[ib];
  for (const auto& d : demos)
    for (const auto& x : d.x) {
      a0 = std::min(a0, x[ia]);
      a1 = std::max(a1, x[ia]);
      b0 = std::min(b0, x[ib]);
      b1 = std::max(b1, x[ib]);
    }
  const double ma = 0.15 * (a1 - a0) + 0.02, mb = 0.15 * (b1 - b0) + 0.02;
  a0 -= ma;
  a1 += ma;
  b0 -= mb;
  b1 += mb;
  ds::HittingDsData data = default_command(model);
  std::vector<std::vector<double>> rows;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Eigen::Vector3d x = xs;
      x[ia] = a0 + (a1 - a0) * i / (n - 1);
      x[ib] = b0 + (b1 - b0) * j / (n - 1);
      const Eigen::Vector3d v = ds::hitting_ds_velocity(model, data, x);
      rows.push_back({x[ia], x[ib], v[ia], v[ib], v.norm()});
    }
  return format_csv({"a", "b", "u", "v", "speed"}, rows);
}

std::string strength_csv(const ds::HittingModel& model,
                         const std::vector<ds::Demonstration>& demos) {
  ds::HittingDsData data = default_command(model);
  std::vector<std::vector<double>> rows;
  for (const auto& d : demos)
    for (std::size_t i = 0; i < d.size(); ++i) {
      const Eigen::Vector3d y = d.x[i] - model.x_star();
      rows.push_back({static_cast<double>(d.id), y.norm(), d.xdot[i].norm(),
                      ds::strength_factor(model, data, y)});
    }
  return format_csv({"demo", "distance", "speed", "strength"}, rows);
}

std::string modulators_csv(const ds::HittingModel& model,
                           const std::vector<ds::Demonstration>& demos,
                           const std::vector<double>& speeds) {
  if (speeds.empty()) throw InputError("modulators: no speeds");
  const double d0 = mean_start_distance(model, demos);
  std::vector<std::string> header{"r"};
  for (double v : speeds) {
    if (!(v > 0.0 && std::isfinite(v)))
      throw InputError(fmt::format("--speeds: {} m/s: expected > 0", v));
    header.push_back(fmt::format("s_constant_{:g}", v));
    header.push_back(fmt::format("s_sine_{:g}", v));
  }
  std::vector<std::vector<double>> rows;
  for (int i = 0; i <= 120; ++i) {
    const double r = 1.2 * d0 * i / 120.0;
    std::vector<double> row{r};
    for (double v : speeds) {
      const double s_d = v / model.default_speed();
      row.push_back(ds::speed_modulator(ds::Modulator::kConstant, s_d, d0, r));
      row.push_back(ds::speed_modulator(ds::Modulator::kSine, s_d, d0, r));
    }
    rows.push_back(row);
  }
  return format_csv(header, rows);
}

std::string heights_csv(const field::Field& f) {
  std::vector<std::vector<double>> rows;
  for (double x = f.bounds[0]; x <= f.bounds[1] + 1e-9; x += 0.02)
    for (double y = f.bounds[2]; y <= f.bounds[3] + 1e-9; y += 0.02)
      rows.push_back({x, y, f.height(x, y)});
  return format_csv({"x", "y", "z"}, rows);
}

std::array<std::array<double, 2>, 4> footprint_corners(const field::Obstacle& obstacle) {
  const field::Footprint fp = obstacle.footprint();
  const double c = std::cos(fp.yaw), s = std::sin(fp.yaw);
  std::array<std::array<double, 2>, 4> out{};
  const int signs[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (int k = 0; k < 4; ++k) {
    const double u = signs[k][0] * fp.half[0], v = signs[k][1] * fp.half[1];
    out[static_cast<std::size_t>(k)] = {fp.center[0] + c * u - s * v, fp.center[1] + s * u + c * v};
  }
  return out;
}

std::string obstacles_csv(const field::Field& f) {
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k < f.obstacles.size(); ++k) {
    const double block = f.obstacles[k].type == field::ObstacleType::kBlock ? 1.0 : 0.0;
    for (const auto& p : footprint_corners(f.obstacles[k]))
      rows.push_back({static_cast<double>(k), block, p[0], p[1]});
  }
  return format_csv({"obstacle", "block", "x", "y"}, rows);
}

std::string trajectory_csv(const sim::PuttOutcome& o) {
  std::vector<std::vector<double>> rows;
  for (const auto& s : o.trajectory) rows.push_back({s.t, s.x, s.y, s.z, s.vx, s.vy, s.vz});
  return format_csv({"t", "x", "y", "z", "vx", "vy", "vz"}, rows);
}

std::string predictions_csv(const learning::Model& model, const learning::Dataset& data) {
  const int ni = model.num_inputs();
  if (ni != 1 && ni != 2)
    throw InputError(fmt::format("plot model: the model has {} inputs; 1 or 2 can be drawn", ni));
  if (data.inputs.rows() == 0) throw InputError(fmt::format("{}: no samples", data.source));
  std::vector<std::array<double, 2>> range(static_cast<std::size_t>(ni));
  for (int k = 0; k < ni; ++k) {
    double lo = data.inputs.col(k).minCoeff(), hi = data.inputs.col(k).maxCoeff();
    const double m = 0.1 * (hi - lo) + 1e-3;
    range[static_cast<std::size_t>(k)] = {lo - m, hi + m};
  }
  const int n = ni == 1 ? 101 : 41;
  const int count = ni == 1 ? n : n * n;
  Eigen::MatrixXd q(count, ni);
  for (int i = 0; i < count; ++i)
    for (int k = 0; k < ni; ++k) {
      const int idx = k == 0 ? (ni == 1 ? i : i / n) : i % n;
      const auto& r = range[static_cast<std::size_t>(k)];
      q(i, k) = r[0] + (r[1] - r[0]) * idx / (n - 1);
    }
  const learning::Predictions p = learning::predict(model, q);
  std::vector<std::string> header = model.input_names;
  for (const auto& o : model.output_names) {
    header.push_back(o + "_mean");
    header.push_back(o + "_std");
  }
  std::vector<std::vector<double>> rows;
  for (int i = 0; i < count; ++i) {
    std::vector<double> row;
    for (int k = 0; k < ni; ++k) row.push_back(q(i, k));
    for (int o = 0; o < model.num_outputs(); ++o) {
      row.push_back(p.mean(i, o));
      row.push_back(p.std(i, o));
    }
    rows.push_back(row);
  }
  return format_csv(header, rows);
}

}  // namespace mg::viz
