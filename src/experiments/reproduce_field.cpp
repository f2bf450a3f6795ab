// The per-field steps of `reproduce` that make its tables: the data sets and the training /
// validation split, the validation MSE, the robot playing test situations, the learning curves
// (reproduce_steps.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <set>
#include <system_error>

#include <fmt/format.h>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/rng.hpp"
#include "experiments/collect.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/reproduce_steps.hpp"
#include "experiments/wire.hpp"
#include "system/distributed.hpp"

namespace mg::experiments::reproduce_steps {

namespace fs = std::filesystem;

namespace {

std::string fmt_pct(double r) {
  return std::isfinite(r) ? fmt::format("{:.0f} %", 100.0 * r) : "-";
}

}  // namespace

learning::Dataset subset(const learning::Dataset& d, const std::vector<int>& rows) {
  learning::Dataset s = d;
  s.inputs.resize(static_cast<Eigen::Index>(rows.size()), d.inputs.cols());
  s.outputs.resize(static_cast<Eigen::Index>(rows.size()), d.outputs.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    s.inputs.row(static_cast<Eigen::Index>(i)) = d.inputs.row(rows[i]);
    s.outputs.row(static_cast<Eigen::Index>(i)) = d.outputs.row(rows[i]);
  }
  return s;
}

learning::TrainOptions train_options(const std::string& method, const std::string& field, int n,
                                     std::uint64_t seed) {
  learning::TrainOptions o;
  o.method = learning::parse_method(method);
  o.seed = seed;
  o.max_gaussians = std::clamp(n / 3, 1, 5);
  if (field == "flat" && o.method != learning::Method::kGpr)
    o.num_gaussians = std::min(2, n);  // thesis 6.2.1
  return o;
}

FieldRun prepare_field(const Run& run, const std::string& name, Tables& t) {
  const ReproduceOptions& opt = run.opt;
  std::error_code ec;
  FieldRun f;
  f.name = name;
  f.sys = std::make_unique<system::System>(system::load_config(opt.config, name), run.run_plant,
                                           run.run_belief);
  const system::System& sys = *f.sys;
  f.region = sys.field().situations;
  if (f.region.balls)
    throw InputError(
        fmt::format("reproduce: field '{}': the thesis's experiments play from the "
                    "tee; its situations have a ball region",
                    name));
  f.teacher.strategy = teacher::parse_strategy(f.region.strategy);
  f.teacher.learn_speed = f.region.learn_speed;
  f.teacher.fixed_speed = f.region.speed;
  const auto points = f.region.collection_points();
  f.split = static_cast<int>(points.size()) >= kSplitMinPoints;
  run.say(fmt::format(
      "{}: {} region, {} collection points, {}", name, field::to_string(f.region.shape),
      points.size(),
      f.split ? "random validation split (thesis arctan protocol)" : "separate validation set"));

  // ---- data sets
  fs::path data_file = run.datasets / (name + ".csv"),
           validation_file = run.datasets / (name + "-validation.csv");
  if (opt.collect) {
    fs::create_directories(opt.out / "datasets", ec);
    data_file = opt.out / "datasets" / (name + ".csv");
    validation_file = opt.out / "datasets" / (name + "-validation.csv");
    CollectOptions co;
    co.teacher = f.teacher;
    co.seed = opt.seed;
    co.threads = opt.threads;
    run.say(fmt::format("{}: collecting {} examples with the teacher", name, points.size()));
    collect(sys, points, co, data_file);
    if (!f.split)
      collect(sys, f.region.sample(kValidationSituations, opt.seed + 6), co, validation_file);
  }
  if (!fs::exists(data_file, ec))
    throw InputError(
        fmt::format("reproduce: data set {} is missing (run with --collect, or "
                    "scripts/make-datasets.sh)",
                    data_file.string()));
  f.table = read_csv(data_file);
  f.inputs = f.region.learner_inputs();
  f.outputs = f.region.learner_outputs();
  f.methods = {"gpr", "gmr"};
  if (f.region.learn_speed) f.methods.push_back("joint-gmr");
  f.all = learning::dataset_from_table(f.table, f.inputs, f.outputs, 2);
  std::vector<std::string> used = f.inputs;
  used.insert(used.end(), f.outputs.begin(), f.outputs.end());
  f.fixed = learning::constant_columns(f.table, {"speed"}, used);
  int full_putts = 0, ball_putts = 0;
  for (double v : f.table.column("full_putts")) full_putts += static_cast<int>(v);
  for (double v : f.table.column("ball_putts")) ball_putts += static_cast<int>(v);
  t.data_md += fmt::format(
      "| {} | {} ({}) | {} of {} | {} | {} | {} |\n", name, field::to_string(f.region.shape),
      f.region.learn_speed ? "angle, speed" : fmt::format("angle at {} m/s", f.region.speed),
      f.all.size(), points.size(), f.region.strategy, full_putts, ball_putts);

  // ---- training / validation sets
  std::vector<int> train_rows, valid_rows;
  f.index = f.table.column("index");
  const std::vector<double>& index_col = f.index;
  if (f.split) {
    const auto v = arctan_validation_split(f.region.counts[0], f.region.counts[1], 9, opt.seed);
    for (int r = 0; r < f.all.size(); ++r) {
      const int idx = static_cast<int>(index_col[static_cast<std::size_t>(r)]);
      (std::binary_search(v.begin(), v.end(), idx) ? valid_rows : train_rows).push_back(r);
    }
    f.train = subset(f.all, train_rows);
    f.validation = subset(f.all, valid_rows);
  } else {
    f.train = f.all;
    if (!fs::exists(validation_file, ec))
      throw InputError(
          fmt::format("reproduce: validation set {} is missing", validation_file.string()));
    f.validation = learning::load_dataset(validation_file, f.inputs, f.outputs);
  }
  // Files for the figures: training and validation points with hole positions.
  const auto write_points = [&](const learning::Dataset& d, const std::string& file) {
    std::vector<std::string> header = f.inputs;
    header.insert(header.end(), f.outputs.begin(), f.outputs.end());
    header.insert(header.end(), {"hole_x", "hole_y"});
    std::vector<std::vector<double>> rows;
    for (int r = 0; r < d.size(); ++r) {
      std::vector<double> row;
      for (int c = 0; c < d.inputs.cols(); ++c) row.push_back(d.inputs(r, c));
      for (int c = 0; c < d.outputs.cols(); ++c) row.push_back(d.outputs(r, c));
      // hole = tee + xi (a 1-D line keeps its fixed coordinate from the region)
      double hx = f.region.from[0] + sys.field().tee[0], hy = f.region.from[1];
      for (std::size_t c = 0; c < f.inputs.size(); ++c) {
        if (f.inputs[c] == "xi_x")
          hx = d.inputs(r, static_cast<Eigen::Index>(c)) + sys.field().tee[0];
        if (f.inputs[c] == "xi_y")
          hy = d.inputs(r, static_cast<Eigen::Index>(c)) + sys.field().tee[1];
      }
      row.push_back(hx);
      row.push_back(hy);
      rows.push_back(row);
    }
    write_file_atomic(file, format_csv(header, rows));
  };
  write_points(f.train, run.csv_path(name + "_train.csv"));
  write_points(f.validation, run.csv_path(name + "_validation.csv"));
  f.data_file = data_file;
  return f;
}

std::map<std::string, learning::Model> validate_models(const Run& run, const FieldRun& f,
                                                       Tables& t) {
  const ReproduceOptions& opt = run.opt;
  const std::string& name = f.name;
  // ---- validation MSE (tables 6.1-6.4)
  std::map<std::string, learning::Model> models;
  for (const auto& m : f.methods) {
    learning::Model model =
        learning::train(f.train, train_options(m, name, f.train.size(), opt.seed));
    model.fixed = f.fixed;
    learning::save_model(model, run.csv_path(fmt::format("{}_{}.json", name, m)));
    std::vector<learning::Score> sc = learning::score(model, f.validation);
    if (f.split) {
      // Mean over random training sets (thesis 6.2.4: 1000 sets, corners always in training).
      std::vector<double> sum(sc.size(), 0.0);
      for (int s = 0; s < run.arctan_splits; ++s) {
        const auto v = arctan_validation_split(f.region.counts[0], f.region.counts[1], 9,
                                               derive_seed(opt.seed, 1000 + s));
        std::vector<int> tr, va;
        for (int r = 0; r < f.all.size(); ++r) {
          const int idx = static_cast<int>(f.index[static_cast<std::size_t>(r)]);
          (std::binary_search(v.begin(), v.end(), idx) ? va : tr).push_back(r);
        }
        const auto ms = learning::train(
            subset(f.all, tr), train_options(m, name, static_cast<int>(tr.size()), opt.seed));
        const auto scs = learning::score(ms, subset(f.all, va));
        for (std::size_t o = 0; o < sc.size(); ++o) sum[o] += scs[o].mse;
      }
      for (std::size_t o = 0; o < sc.size(); ++o) sc[o].mse = sum[o] / run.arctan_splits;
    }
    for (std::size_t o = 0; o < sc.size(); ++o) {
      const bool angle = f.outputs[o] == "angle";
      const double ours = angle ? sc[o].mse * kDeg * kDeg : sc[o].mse;
      const double th = run.thesis.mse(name, f.outputs[o], m);
      t.mse_md += fmt::format("| {} | {} | {} | {:.4g} {} | {} |\n", name, f.outputs[o], m, ours,
                              angle ? "deg²" : "(m/s)²",
                              std::isfinite(th) ? fmt::format("{:.4g}", th) : "-");
    }
    models.emplace(m, std::move(model));
  }
  run.say(fmt::format("{}: trained {} on {} examples, validated on {}", name,
                      fmt::join(f.methods, ", "), f.train.size(), f.validation.size()));
  return models;
}

void play_test_situations(const Run& run, const FieldRun& f,
                          const std::map<std::string, learning::Model>& models, Tables& t) {
  const ReproduceOptions& opt = run.opt;
  const system::System& sys = *f.sys;
  const std::string& name = f.name;
  // ---- the robot plays (table 6.5), oracle once per test set
  const auto test_holes = f.region.sample(run.n_test, opt.seed);
  std::vector<teacher::Example> oracle(test_holes.size());
  int oracle_done = 0;
  system::distributed_for(
      sys, oracle, opt.threads,
      [&](int i, system::SystemData& d) {
        oracle[static_cast<std::size_t>(i)] =
            teacher::teach(sys, d, test_holes[static_cast<std::size_t>(i)], f.teacher);
      },
      [&](int) {
        if (++oracle_done % 10 == 0 || oracle_done == run.n_test)
          run.say(fmt::format("{}: oracle teacher {}/{}", name, oracle_done, run.n_test));
      });
  const auto ceiling = [&](int n) {
    int k = 0;
    for (int i = 0; i < n; ++i) k += oracle[static_cast<std::size_t>(i)].found;
    return static_cast<double>(k) / n;
  };
  std::vector<std::pair<std::string, const learning::Model*>> players;
  for (const auto& m : f.methods) players.emplace_back(m, &models.at(m));
  learning::Model full_set_models[3];
  if (f.split) {  // thesis: the arctan models trained on the full data set too
    for (std::size_t k = 0; k < f.methods.size(); ++k) {
      full_set_models[k] =
          learning::train(f.all, train_options(f.methods[k], name, f.all.size(), opt.seed));
      full_set_models[k].fixed = f.fixed;
      players.emplace_back(f.methods[k] + " (full data set)", &full_set_models[k]);
    }
  }
  std::vector<std::array<double, 2>> first30(test_holes.begin(),
                                             test_holes.begin() + std::min(30, run.n_test));
  std::string traj_args;
  for (const auto& [label, model] : players) {
    EvaluateOptions eo;
    eo.situations = run.n_test;
    eo.seed = opt.seed;
    eo.threads = opt.threads;
    eo.oracle = false;
    const Evaluation e = evaluate_model(sys, *model, f.region, eo);
    const std::string tag =
        label.substr(0, label.find(' ')) + (label.find("full") != std::string::npos ? "_full" : "");
    write_file_atomic(run.csv_path(fmt::format("{}_{}_evaluation.csv", name, tag)),
                      evaluation_csv(e, sys.field()));
    const auto row = [&](int n) {
      int k = 0;
      for (int i = 0; i < n; ++i) k += e.rows[static_cast<std::size_t>(i)].sunk;
      const auto ci = wilson_interval(k, n);
      // The thesis played 30 situations; its arctan full-data-set rows are their own table part.
      const bool full_set = label.find("full") != std::string::npos;
      const double th =
          n != 30    ? NAN
          : full_set ? run.thesis.success(name + "_full_data_set", label.substr(0, label.find(' ')))
                     : run.thesis.success(name, label);
      t.success_md += fmt::format("| {} | {} | {} | {} | {:.0f} % ({:.0f}-{:.0f} %) | {} | {} |\n",
                                  name, label, n, k, 100.0 * k / n, 100.0 * ci[0], 100.0 * ci[1],
                                  fmt_pct(ceiling(n)), fmt_pct(th));
      t.success_csv +=
          fmt::format("{},{},{},{},{},{},{},{},{}\n", name, label, n, k, static_cast<double>(k) / n,
                      ci[0], ci[1], ceiling(n), std::isfinite(th) ? fmt::format("{}", th) : "");
    };
    row(std::min(30, run.n_test));
    if (run.n_test > 30) row(run.n_test);
    run.say(fmt::format("{}: {} sank {} of {}", name, label, e.sunk, run.n_test));
  }
}

void learning_curves(const Run& run, const FieldRun& f, Tables& t) {
  const ReproduceOptions& opt = run.opt;
  const system::System& sys = *f.sys;
  const std::string& name = f.name;
  // ---- learning curves (beyond the thesis): success against training examples
  const int n_all = f.train.size();
  std::set<int> sizes;
  for (double q : {0.25, 0.5, 0.75, 1.0})
    sizes.insert(std::clamp(static_cast<int>(std::lround(q * n_all)), 3, n_all));
  std::string curve = "method,x,median,p10,p90\n";
  for (const std::string m : {"gpr", "gmr"}) {
    for (int s : sizes) {
      std::vector<double> ratios;
      for (int seed = 0; seed < (s == n_all ? 1 : run.curve_seeds); ++seed) {
        std::vector<int> rows(static_cast<std::size_t>(n_all));
        std::iota(rows.begin(), rows.end(), 0);
        Rng rng(derive_seed(opt.seed, 7000 + 100 * s + seed));
        std::shuffle(rows.begin(), rows.end(), rng);
        rows.resize(static_cast<std::size_t>(s));
        std::sort(rows.begin(), rows.end());
        learning::Model model =
            learning::train(subset(f.train, rows), train_options(m, name, s, opt.seed));
        model.fixed = f.fixed;
        EvaluateOptions eo;
        eo.situations = run.curve_situations;
        eo.seed = opt.seed;
        eo.threads = opt.threads;
        eo.oracle = false;
        ratios.push_back(evaluate_model(sys, model, f.region, eo).success_ratio);
      }
      std::sort(ratios.begin(), ratios.end());
      const auto q = [&](double p) {
        return ratios[static_cast<std::size_t>(std::lround(p * (ratios.size() - 1)))];
      };
      curve += fmt::format("{},{},{},{},{}\n", m, s, q(0.5), q(0.1), q(0.9));
      t.curves_md += fmt::format("| {} | {} | {} | {:.0f} % | {:.0f}-{:.0f} % |\n", name, m, s,
                                 100.0 * q(0.5), 100.0 * q(0.1), 100.0 * q(0.9));
    }
  }
  write_file_atomic(run.csv_path(name + "_learning_curve.csv"), curve);
  run.say(fmt::format("{}: learning curves done", name));
  run.plot(
      fmt::format("learning-curve {} {} --title {}",
                  shell_quote(run.csv_path(name + "_learning_curve.csv")),
                  shell_quote(run.fig_path(name + "_learning_curve.png")),
                  shell_quote(fmt::format("{}: success on {} test situations vs training examples",
                                          name, run.curve_situations))),
      run.fig_path(name + "_learning_curve.png"));
}

}  // namespace mg::experiments::reproduce_steps
