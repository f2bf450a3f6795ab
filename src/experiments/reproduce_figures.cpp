// The per-field figures of `reproduce` (reproduce_steps.hpp): each model's predictions over the
// region, the data set, the field's height map with ball paths of data-set launches, and the
// sinking window around the example nearest the field's hole.
#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "core/io.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/reproduce_steps.hpp"
#include "experiments/sweep.hpp"
#include "experiments/wire.hpp"

namespace mg::experiments::reproduce_steps {

void field_figures(const Run& run, const FieldRun& f,
                   const std::map<std::string, learning::Model>& models, Tables& t) {
  const ReproduceOptions& opt = run.opt;
  const system::System& sys = *f.sys;
  const std::string& name = f.name;
  // ---- figures: predictions, data set, field with ball paths, sinking window
  std::vector<std::array<double, 2>> grid;
  if (f.inputs.size() == 1) {
    for (int i = 0; i <= 100; ++i) {
      const double s = i / 100.0;
      grid.push_back({f.region.from[0] + s * (f.region.to[0] - f.region.from[0]),
                      f.region.from[1] + s * (f.region.to[1] - f.region.from[1])});
    }
  } else {
    const double x0 = f.region.shape == field::RegionShape::kList
                          ? f.all.inputs.col(0).minCoeff() + sys.field().tee[0]
                          : f.region.x_range[0];
    const double x1 = f.region.shape == field::RegionShape::kList
                          ? f.all.inputs.col(0).maxCoeff() + sys.field().tee[0]
                          : f.region.x_range[1];
    const double y0 = f.region.shape == field::RegionShape::kList
                          ? f.all.inputs.col(1).minCoeff() + sys.field().tee[1]
                          : f.region.y_range[0];
    const double y1 = f.region.shape == field::RegionShape::kList
                          ? f.all.inputs.col(1).maxCoeff() + sys.field().tee[1]
                          : f.region.y_range[1];
    for (int i = 0; i < 25; ++i)
      for (int j = 0; j < 25; ++j)
        grid.push_back({x0 + (x1 - x0) * i / 24.0, y0 + (y1 - y0) * j / 24.0});
  }
  for (const auto& m : f.methods) {
    const auto pred = predict_hits(models.at(m), sys.field(), grid);
    std::vector<std::string> header = f.inputs;
    for (const auto& o : f.outputs) {
      header.push_back(o + "_mean");
      header.push_back(o + "_std");
    }
    std::vector<std::vector<double>> rows;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      std::vector<double> row;
      for (const auto& in : f.inputs)
        row.push_back(in == "xi_x" ? grid[i][0] - sys.field().tee[0]
                                   : grid[i][1] - sys.field().tee[1]);
      row.push_back(pred[i].angle);
      row.push_back(pred[i].angle_std);
      if (f.region.learn_speed) {
        row.push_back(pred[i].speed);
        row.push_back(pred[i].speed_std);
      }
      rows.push_back(row);
    }
    const std::string p = run.csv_path(fmt::format("{}_{}_predictions.csv", name, m));
    write_file_atomic(p, format_csv(header, rows));
    for (const auto& o : f.outputs) {
      const std::string png = fmt::format("{}_{}_{}.png", name, m, o);
      run.plot(
          fmt::format("model --predictions {} --train {} --validation {} --output {} {} --title {}",
                      shell_quote(p), shell_quote(run.csv_path(name + "_train.csv")),
                      shell_quote(run.csv_path(name + "_validation.csv")), o,
                      shell_quote(run.fig_path(png)),
                      shell_quote(fmt::format("{} {}: {} (mean ± 2σ)", name, m, o))),
          run.fig_path(png));
      t.figures_md += fmt::format("![{} {} {}](figures/{})\n", name, m, o, png);
    }
  }
  run.plot(fmt::format("dataset {} {} --validation {} --title {}",
                       shell_quote(run.csv_path(name + "_train.csv")),
                       shell_quote(run.fig_path(name + "_dataset.png")),
                       shell_quote(run.csv_path(name + "_validation.csv")),
                       shell_quote(fmt::format(
                           "{}: training (green) and validation (red) situations", name))),
           run.fig_path(name + "_dataset.png"));
  t.figures_md += fmt::format("![{} data set](figures/{}_dataset.png)\n", name, name);
  // Field height map with the ball paths of the data set's launches (ball-only replays).
  const auto& fl = sys.field();
  std::vector<std::vector<double>> heights;
  for (double x = fl.bounds[0]; x <= fl.bounds[1] + 1e-9; x += 0.02)
    for (double y = fl.bounds[2]; y <= fl.bounds[3] + 1e-9; y += 0.02)
      heights.push_back({x, y, fl.height(x, y)});
  write_file_atomic(run.csv_path(name + "_heights.csv"), format_csv({"x", "y", "z"}, heights));
  std::string args;
  system::SystemData d(sys);
  const auto la = f.table.column("launch_angle"), ls = f.table.column("launch_speed");
  const auto hx = f.table.column("hole_x"), hy = f.table.column("hole_y");
  const int n_paths = std::min<int>(6, static_cast<int>(la.size()));
  for (int k = 0; k < n_paths; ++k) {
    const auto r =
        static_cast<std::size_t>(k * (static_cast<int>(la.size()) - 1) / std::max(1, n_paths - 1));
    const auto out = system::ball_putt(sys, d, {hx[r], hy[r]}, la[r], ls[r], 0.01);
    std::vector<std::vector<double>> rows;
    for (const auto& s : out.trajectory) rows.push_back({s.t, s.x, s.y, s.z, s.vx, s.vy, s.vz});
    const std::string t = run.csv_path(fmt::format("{}_path_{}.csv", name, k));
    write_file_atomic(t, format_csv({"t", "x", "y", "z", "vx", "vy", "vz"}, rows));
    args += fmt::format(" --trajectory {} --hole={},{}", shell_quote(t), hx[r], hy[r]);
  }
  run.plot(
      fmt::format(
          "field {} {}{} --tee={},{} --title {}", shell_quote(run.csv_path(name + "_heights.csv")),
          shell_quote(run.fig_path(name + "_field.png")), args, fl.tee[0], fl.tee[1],
          shell_quote(fmt::format(
              "{}: height map and ball paths of data-set launches (ball-only replays)", name))),
      run.fig_path(name + "_field.png"));
  t.figures_md += fmt::format("![{} field](figures/{}_field.png)\n", name, name);
  // Sinking window at the field's own hole around the nearest example.
  std::size_t best = 0;
  for (std::size_t r = 0; r < hx.size(); ++r)
    if (std::hypot(hx[r] - fl.hole.position[0], hy[r] - fl.hole.position[1]) <
        std::hypot(hx[best] - fl.hole.position[0], hy[best] - fl.hole.position[1]))
      best = r;
  SweepOptions so;
  so.hole = {hx[best], hy[best]};
  const double a0 = f.table.column("angle")[best], v0 = f.table.column("speed")[best];
  const int na = opt.quick ? 9 : 17, nv = opt.quick ? 11 : 21;
  so.angles = linspace(a0 - 0.04, a0 + 0.04, na);
  so.speeds = linspace(std::max(sys.config().speed_min, v0 - 0.3),
                       std::min(sys.module().club_speed_cap(a0 - 0.04), v0 + 0.3), nv);
  so.threads = opt.threads;
  const auto cells = run_sweep(sys, so);
  write_file_atomic(run.csv_path(name + "_sweep.csv"), sweep_csv(cells));
  run.plot(fmt::format("sweep {} {} --title {}", shell_quote(run.csv_path(name + "_sweep.csv")),
                       shell_quote(run.fig_path(name + "_sweep.png")),
                       shell_quote(fmt::format("{}: sinking window at hole ({:.2f}, {:.2f}), arm",
                                               name, so.hole[0], so.hole[1]))),
           run.fig_path(name + "_sweep.png"));
  t.figures_md += fmt::format("![{} sinking window](figures/{}_sweep.png)\n", name, name);
  run.say(fmt::format("{}: figures done", name));
}

}  // namespace mg::experiments::reproduce_steps
