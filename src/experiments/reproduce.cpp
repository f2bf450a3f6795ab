#include "experiments/reproduce.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numeric>
#include <set>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "core/plot.hpp"
#include "core/rng.hpp"
#include "experiments/beyond.hpp"
#include "experiments/collect.hpp"
#include "experiments/evaluate.hpp"
#include "experiments/real_robot.hpp"
#include "experiments/round_study.hpp"
#include "experiments/sweep.hpp"
#include "experiments/wire.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"
#include "system/distributed.hpp"

namespace mg::experiments {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = 180.0 / 3.14159265358979323846;
/// Regions with at least this many collection points use the thesis's arctan protocol (random
/// validation points from the data set); smaller ones a separate validation set.
constexpr int kSplitMinPoints = 24;
constexpr int kValidationSituations = 10;

std::string fmt_pct(double r) {
  return std::isfinite(r) ? fmt::format("{:.0f} %", 100.0 * r) : "-";
}

/// The thesis's chapter-6 values (data/reference/thesis-results.yaml), for the "thesis" columns.
struct Thesis {
  YAML::Node root;
  static std::string key(const std::string& field) {
    std::string k = field;
    std::replace(k.begin(), k.end(), '-', '_');
    return k;
  }
  /// MSE of (field, output, method) as printed, or NaN.
  double mse(const std::string& field, const std::string& output, const std::string& method) const {
    std::string m = method;
    std::replace(m.begin(), m.end(), '-', '_');
    const YAML::Node mse = root["mse"];
    if (!mse || !mse.IsMap() || !mse[key(field)]) return NAN;
    const YAML::Node f = mse[key(field)];
    // (yaml-cpp: assigning to a Node writes through, so pick the node without reassigning)
    const YAML::Node o = f[output] ? f[output] : f["simulator_" + output];
    return o && o.IsMap() && o[m] ? o[m].as<double>() : NAN;
  }
  /// Success ratio of (field, method) `where` ("simulator" | "real_robot"), or NaN.
  double success(const std::string& field, const std::string& method,
                 const char* where = "simulator") const {
    std::string m = method;
    std::replace(m.begin(), m.end(), '-', '_');
    const YAML::Node s = root["success"];
    if (!s || !s.IsMap() || !s[key(field)]) return NAN;
    const YAML::Node f = s[key(field)];
    if (!f[where] || !f[where][m]) return NAN;
    const YAML::Node c = f[where][m];
    return c[1].as<double>() / c[0].as<double>();
  }
};

Thesis load_thesis() {
  const fs::path p = data_dir() / "reference" / "thesis-results.yaml";
  try {
    return Thesis{YAML::Load(read_text_file(p))};
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: malformed YAML: {}", p.string(), e.what()));
  }
}

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

/// Everything about one field's run.
struct FieldRun {
  std::string name;
  std::unique_ptr<system::System> sys;
  field::Situations region;
  CsvTable table;         ///< the data set as read
  learning::Dataset all;  ///< every example
  std::vector<std::string> inputs, outputs, methods;
  bool split = false;                   ///< arctan protocol
  learning::Dataset train, validation;  ///< the thesis's training / validation sets
  std::vector<std::pair<std::string, double>> fixed;
  teacher::TeacherOptions teacher;
};

}  // namespace

std::vector<int> arctan_validation_split(int nx, int ny, int n_validation, std::uint64_t seed) {
  std::vector<int> candidates;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const bool corner = (i == 0 || i == nx - 1) && (j == 0 || j == ny - 1);
      if (!corner) candidates.push_back(i * ny + j);
    }
  Rng rng(seed);
  std::shuffle(candidates.begin(), candidates.end(), rng);
  candidates.resize(
      static_cast<std::size_t>(std::min<int>(n_validation, static_cast<int>(candidates.size()))));
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

void reproduce(const ReproduceOptions& opt, const std::function<void(const std::string&)>& log) {
  const auto t_start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  };
  const auto say = [&](const std::string& s) { log(fmt::format("[{:6.1f} s] {}", elapsed(), s)); };
  const Thesis thesis = load_thesis();
  const fs::path datasets = opt.datasets.empty() ? data_dir() / "datasets" : opt.datasets;
  std::error_code ec;
  if (opt.fields.empty()) throw InputError("reproduce: --fields: expected at least one field");
  for (const auto& name : opt.fields) {  // every input checked before any work starts
    const field::Field fl = field::load_field(name);
    const bool split =
        static_cast<int>(fl.situations.collection_points().size()) >= kSplitMinPoints;
    if (opt.collect) continue;
    for (const fs::path& p : {datasets / (name + ".csv"), datasets / (name + "-validation.csv")}) {
      if (split && p.filename().string().ends_with("-validation.csv")) continue;
      if (!fs::is_regular_file(p, ec))
        throw InputError(
            fmt::format("reproduce: data set {} is missing (run with --collect, or "
                        "scripts/make-datasets.sh)",
                        p.string()));
    }
  }
  fs::create_directories(opt.out / "csv", ec);
  fs::create_directories(opt.out / "figures", ec);
  if (ec) throw IoError(fmt::format("-o: cannot create '{}': {}", opt.out.string(), ec.message()));
  const int n_test = opt.quick ? 30 : 200;
  const int curve_seeds = opt.quick ? 3 : 10;
  const int curve_situations = 30;
  const int arctan_splits = opt.quick ? 100 : 1000;

  std::string report;
  std::string mse_md, success_md, curves_md, data_md, figures_md;
  std::map<std::string, std::string> beyond_md;
  std::map<std::string, std::string> real_md;
  const plant::Plant run_plant = opt.plant.empty() ? plant::Plant{} : plant::load_plant(opt.plant);
  const plant::Plant real_plant = plant::load_plant(
      opt.real_robot_plant.empty() ? (data_dir() / "plants" / "real-wam.yaml").string()
                                   : opt.real_robot_plant);
  std::vector<std::vector<double>> mse_rows;
  std::string success_csv =
      "field,method,situations,sunk,success_ratio,ci_lo,ci_hi,oracle_ceiling,thesis_ratio\n";
  nlohmann::json run_json = {{"seed", opt.seed},
                             {"quick", opt.quick},
                             {"revision", opt.revision},
                             {"threads", system::thread_count(opt.threads)},
                             {"fields", nlohmann::json::array()}};
  run_json["plant"] = run_plant.source.empty()
                          ? nlohmann::json()
                          : nlohmann::json{{"path", run_plant.source}, {"hash", run_plant.hash}};
  const auto plot = [&](const std::string& args, const std::string& png) {
    if (!opt.plots || !system::is_root_process()) return;  // one process draws (MPI)
    run_plot_script(args, png);
  };
  const auto csv_path = [&](const std::string& name) { return (opt.out / "csv" / name).string(); };
  const auto fig_path = [&](const std::string& name) {
    return (opt.out / "figures" / name).string();
  };

  for (const std::string& name : opt.fields) {
    FieldRun f;
    f.name = name;
    f.sys = std::make_unique<system::System>(system::load_config(opt.config, name), run_plant);
    const system::System& sys = *f.sys;
    f.region = sys.field().situations;
    f.teacher.strategy = teacher::parse_strategy(f.region.strategy);
    f.teacher.learn_speed = f.region.learn_speed;
    f.teacher.fixed_speed = f.region.speed;
    const auto points = f.region.collection_points();
    f.split = static_cast<int>(points.size()) >= kSplitMinPoints;
    say(fmt::format(
        "{}: {} region, {} collection points, {}", name, field::to_string(f.region.shape),
        points.size(),
        f.split ? "random validation split (thesis arctan protocol)" : "separate validation set"));

    // ---- data sets
    fs::path data_file = datasets / (name + ".csv"),
             validation_file = datasets / (name + "-validation.csv");
    if (opt.collect) {
      fs::create_directories(opt.out / "datasets", ec);
      data_file = opt.out / "datasets" / (name + ".csv");
      validation_file = opt.out / "datasets" / (name + "-validation.csv");
      CollectOptions co;
      co.teacher = f.teacher;
      co.seed = opt.seed;
      co.threads = opt.threads;
      say(fmt::format("{}: collecting {} examples with the teacher", name, points.size()));
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
    data_md += fmt::format(
        "| {} | {} ({}) | {} of {} | {} | {} | {} |\n", name, field::to_string(f.region.shape),
        f.region.learn_speed ? "angle, speed" : fmt::format("angle at {} m/s", f.region.speed),
        f.all.size(), points.size(), f.region.strategy, full_putts, ball_putts);

    // ---- training / validation sets
    std::vector<int> train_rows, valid_rows;
    const std::vector<double> index_col = f.table.column("index");
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
    write_points(f.train, csv_path(name + "_train.csv"));
    write_points(f.validation, csv_path(name + "_validation.csv"));

    // ---- validation MSE (tables 6.1-6.4)
    std::map<std::string, learning::Model> models;
    for (const auto& m : f.methods) {
      learning::Model model =
          learning::train(f.train, train_options(m, name, f.train.size(), opt.seed));
      model.fixed = f.fixed;
      learning::save_model(model, csv_path(fmt::format("{}_{}.json", name, m)));
      std::vector<learning::Score> sc = learning::score(model, f.validation);
      if (f.split) {
        // Mean over random training sets (thesis 6.2.4: 1000 sets, corners always in training).
        std::vector<double> sum(sc.size(), 0.0);
        for (int s = 0; s < arctan_splits; ++s) {
          const auto v = arctan_validation_split(f.region.counts[0], f.region.counts[1], 9,
                                                 derive_seed(opt.seed, 1000 + s));
          std::vector<int> tr, va;
          for (int r = 0; r < f.all.size(); ++r) {
            const int idx = static_cast<int>(index_col[static_cast<std::size_t>(r)]);
            (std::binary_search(v.begin(), v.end(), idx) ? va : tr).push_back(r);
          }
          const auto ms = learning::train(
              subset(f.all, tr), train_options(m, name, static_cast<int>(tr.size()), opt.seed));
          const auto scs = learning::score(ms, subset(f.all, va));
          for (std::size_t o = 0; o < sc.size(); ++o) sum[o] += scs[o].mse;
        }
        for (std::size_t o = 0; o < sc.size(); ++o) sc[o].mse = sum[o] / arctan_splits;
      }
      for (std::size_t o = 0; o < sc.size(); ++o) {
        const bool angle = f.outputs[o] == "angle";
        const double ours = angle ? sc[o].mse * kDeg * kDeg : sc[o].mse;
        const double th = thesis.mse(name, f.outputs[o], m);
        mse_md += fmt::format("| {} | {} | {} | {:.4g} {} | {} |\n", name, f.outputs[o], m, ours,
                              angle ? "deg²" : "(m/s)²",
                              std::isfinite(th) ? fmt::format("{:.4g}", th) : "-");
        mse_rows.push_back({static_cast<double>(mse_rows.size()), ours, th});
      }
      models.emplace(m, std::move(model));
    }
    say(fmt::format("{}: trained {} on {} examples, validated on {}", name,
                    fmt::join(f.methods, ", "), f.train.size(), f.validation.size()));

    // ---- the robot plays (table 6.5), oracle once per test set
    const auto test_holes = f.region.sample(n_test, opt.seed);
    std::vector<teacher::Example> oracle(test_holes.size());
    int oracle_done = 0;
    system::distributed_for(
        sys, oracle, opt.threads,
        [&](int i, system::SystemData& d) {
          oracle[static_cast<std::size_t>(i)] =
              teacher::teach(sys, d, test_holes[static_cast<std::size_t>(i)], f.teacher);
        },
        [&](int) {
          if (++oracle_done % 10 == 0 || oracle_done == n_test)
            say(fmt::format("{}: oracle teacher {}/{}", name, oracle_done, n_test));
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
                                               test_holes.begin() + std::min(30, n_test));
    std::string traj_args;
    for (const auto& [label, model] : players) {
      EvaluateOptions eo;
      eo.situations = n_test;
      eo.seed = opt.seed;
      eo.threads = opt.threads;
      eo.oracle = false;
      const Evaluation e = evaluate_model(sys, *model, f.region, eo);
      const std::string tag = label.substr(0, label.find(' ')) +
                              (label.find("full") != std::string::npos ? "_full" : "");
      write_file_atomic(csv_path(fmt::format("{}_{}_evaluation.csv", name, tag)),
                        evaluation_csv(e, sys.field()));
      const auto row = [&](int n) {
        int k = 0;
        for (int i = 0; i < n; ++i) k += e.rows[static_cast<std::size_t>(i)].sunk;
        const auto ci = wilson_interval(k, n);
        // The thesis played 30 situations; its arctan full-data-set rows are their own table part.
        const bool full_set = label.find("full") != std::string::npos;
        const double th =
            n != 30    ? NAN
            : full_set ? thesis.success(name + "_full_data_set", label.substr(0, label.find(' ')))
                       : thesis.success(name, label);
        success_md += fmt::format("| {} | {} | {} | {} | {:.0f} % ({:.0f}-{:.0f} %) | {} | {} |\n",
                                  name, label, n, k, 100.0 * k / n, 100.0 * ci[0], 100.0 * ci[1],
                                  fmt_pct(ceiling(n)), fmt_pct(th));
        success_csv += fmt::format("{},{},{},{},{},{},{},{},{}\n", name, label, n, k,
                                   static_cast<double>(k) / n, ci[0], ci[1], ceiling(n),
                                   std::isfinite(th) ? fmt::format("{}", th) : "");
      };
      row(std::min(30, n_test));
      if (n_test > 30) row(n_test);
      say(fmt::format("{}: {} sank {} of {}", name, label, e.sunk, n_test));
    }

    // ---- learning curves (beyond the thesis): success against training examples
    {
      const int n_all = f.train.size();
      std::set<int> sizes;
      for (double q : {0.25, 0.5, 0.75, 1.0})
        sizes.insert(std::clamp(static_cast<int>(std::lround(q * n_all)), 3, n_all));
      std::string curve = "method,x,median,p10,p90\n";
      for (const std::string m : {"gpr", "gmr"}) {
        for (int s : sizes) {
          std::vector<double> ratios;
          for (int seed = 0; seed < (s == n_all ? 1 : curve_seeds); ++seed) {
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
            eo.situations = curve_situations;
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
          curves_md += fmt::format("| {} | {} | {} | {:.0f} % | {:.0f}-{:.0f} % |\n", name, m, s,
                                   100.0 * q(0.5), 100.0 * q(0.1), 100.0 * q(0.9));
        }
      }
      write_file_atomic(csv_path(name + "_learning_curve.csv"), curve);
      say(fmt::format("{}: learning curves done", name));
      plot(fmt::format(
               "learning-curve {} {} --title {}",
               shell_quote(csv_path(name + "_learning_curve.csv")),
               shell_quote(fig_path(name + "_learning_curve.png")),
               shell_quote(fmt::format("{}: success on {} test situations vs training examples",
                                       name, curve_situations))),
           fig_path(name + "_learning_curve.png"));
    }

    // ---- beyond the thesis: the robot teaches itself; baselines; noise
    if (opt.beyond) {
      BeyondOptions bo;
      bo.quick = opt.quick;
      bo.threads = opt.threads;
      bo.seed = opt.seed;
      bo.test_situations = n_test;
      bo.teacher = f.teacher;
      bo.csv_path = csv_path;
      bo.fig_path = fig_path;
      bo.plot = plot;
      bo.say = say;
      for (const auto& [table, rows] : beyond_thesis(sys, name, f.region, models, bo))
        beyond_md[table] += rows;
    }

    // ---- the real-robot rows: a plant stands in for the real WAM (the thesis's real fields)
    if (opt.real_robot && (name == "flat" || name == "multiple-hills")) {
      RealRobotOptions ro;
      ro.quick = opt.quick;
      ro.threads = opt.threads;
      ro.seed = opt.seed;
      ro.plant = real_plant;
      ro.thesis = [&](const std::string& fl, const std::string& m) {
        return thesis.success(fl, m, "real_robot");
      };
      ro.csv_path = csv_path;
      ro.fig_path = fig_path;
      ro.plot = plot;
      ro.say = say;
      for (const auto& [table, rows] : real_robot_rows(sys.config(), name, f.region, models, ro))
        real_md[table] += rows;
    }

    // ---- figures: predictions, data set, field with ball paths, sinking window
    {
      std::vector<std::array<double, 2>> grid;
      std::vector<std::vector<double>> qrows;
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
        const std::string p = csv_path(fmt::format("{}_{}_predictions.csv", name, m));
        write_file_atomic(p, format_csv(header, rows));
        for (const auto& o : f.outputs) {
          const std::string png = fmt::format("{}_{}_{}.png", name, m, o);
          plot(fmt::format(
                   "model --predictions {} --train {} --validation {} --output {} {} --title {}",
                   shell_quote(p), shell_quote(csv_path(name + "_train.csv")),
                   shell_quote(csv_path(name + "_validation.csv")), o, shell_quote(fig_path(png)),
                   shell_quote(fmt::format("{} {}: {} (mean ± 2σ)", name, m, o))),
               fig_path(png));
          figures_md += fmt::format("![{} {} {}](figures/{})\n", name, m, o, png);
        }
      }
      plot(fmt::format("dataset {} {} --validation {} --title {}",
                       shell_quote(csv_path(name + "_train.csv")),
                       shell_quote(fig_path(name + "_dataset.png")),
                       shell_quote(csv_path(name + "_validation.csv")),
                       shell_quote(fmt::format(
                           "{}: training (green) and validation (red) situations", name))),
           fig_path(name + "_dataset.png"));
      figures_md += fmt::format("![{} data set](figures/{}_dataset.png)\n", name, name);
      // Field height map with the ball paths of the data set's launches (ball-only replays).
      const auto& fl = sys.field();
      std::vector<std::vector<double>> heights;
      for (double x = fl.bounds[0]; x <= fl.bounds[1] + 1e-9; x += 0.02)
        for (double y = fl.bounds[2]; y <= fl.bounds[3] + 1e-9; y += 0.02)
          heights.push_back({x, y, fl.height(x, y)});
      write_file_atomic(csv_path(name + "_heights.csv"), format_csv({"x", "y", "z"}, heights));
      std::string args;
      system::SystemData d(sys);
      const auto la = f.table.column("launch_angle"), ls = f.table.column("launch_speed");
      const auto hx = f.table.column("hole_x"), hy = f.table.column("hole_y");
      const int n_paths = std::min<int>(6, static_cast<int>(la.size()));
      for (int k = 0; k < n_paths; ++k) {
        const auto r = static_cast<std::size_t>(k * (static_cast<int>(la.size()) - 1) /
                                                std::max(1, n_paths - 1));
        const auto out = system::ball_putt(sys, d, {hx[r], hy[r]}, la[r], ls[r], 0.01);
        std::vector<std::vector<double>> rows;
        for (const auto& s : out.trajectory) rows.push_back({s.t, s.x, s.y, s.z, s.vx, s.vy, s.vz});
        const std::string t = csv_path(fmt::format("{}_path_{}.csv", name, k));
        write_file_atomic(t, format_csv({"t", "x", "y", "z", "vx", "vy", "vz"}, rows));
        args += fmt::format(" --trajectory {} --hole={},{}", shell_quote(t), hx[r], hy[r]);
      }
      plot(
          fmt::format(
              "field {} {}{} --tee={},{} --title {}", shell_quote(csv_path(name + "_heights.csv")),
              shell_quote(fig_path(name + "_field.png")), args, fl.tee[0], fl.tee[1],
              shell_quote(fmt::format(
                  "{}: height map and ball paths of data-set launches (ball-only replays)", name))),
          fig_path(name + "_field.png"));
      figures_md += fmt::format("![{} field](figures/{}_field.png)\n", name, name);
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
      write_file_atomic(csv_path(name + "_sweep.csv"), sweep_csv(cells));
      plot(fmt::format("sweep {} {} --title {}", shell_quote(csv_path(name + "_sweep.csv")),
                       shell_quote(fig_path(name + "_sweep.png")),
                       shell_quote(fmt::format("{}: sinking window at hole ({:.2f}, {:.2f}), arm",
                                               name, so.hole[0], so.hole[1]))),
           fig_path(name + "_sweep.png"));
      figures_md += fmt::format("![{} sinking window](figures/{}_sweep.png)\n", name, name);
      say(fmt::format("{}: figures done", name));
    }
    run_json["fields"].push_back({{"name", name},
                                  {"source", sys.field().source},
                                  {"region", field::to_string(f.region.shape)},
                                  {"strategy", f.region.strategy},
                                  {"learn_speed", f.region.learn_speed},
                                  {"fixed_speed", f.region.speed},
                                  {"data_set", data_file.string()},
                                  {"inputs", f.inputs},
                                  {"outputs", f.outputs},
                                  {"hitting_model", sys.config().hitting_model},
                                  {"envelope",
                                   {sys.config().angle_min, sys.config().angle_max,
                                    sys.config().speed_min, sys.config().speed_max}}});
  }

  std::string rounds_md;  // beyond the thesis: a round of minigolf
  const int round_seeds = opt.round_seeds >= 0 ? opt.round_seeds : (opt.quick ? 3 : 20);
  if (opt.beyond && round_seeds > 0) {
    RoundStudyOptions ro;
    ro.seeds = round_seeds;
    ro.seed = opt.seed;
    ro.threads = opt.threads;
    ro.config = opt.config;
    ro.plant = opt.plant;
    ro.plots = opt.plots;
    rounds_md =
        "\n## Beyond the thesis: a round of minigolf\n\n"
        "Every shipped course, hole after hole from wherever the ball lies (docs/round.md). "
        "**robot**: plans in its own model of each field and hits with the arm (full system), "
        "its launch skill learned from its own putts on each field; **oracle**: plans in the "
        "true world with exact execution, ball-only putts (the best this planner can do); "
        "**greedy**: aims the arm at the hole. Strokes include penalties; a hole ends at "
        "`max_strokes`. Every stroke: `rounds.csv`.\n\n" +
        round_study(ro, opt.out, say).markdown;
  }
  write_file_atomic(opt.out / "csv" / "success.csv", success_csv);
  plot(fmt::format(
           "success {} {} --title {}", shell_quote(csv_path("success.csv")),
           shell_quote(fig_path("success.png")),
           shell_quote(
               "success ratio per field and method (95 % Wilson interval; o = oracle ceiling)")),
       fig_path("success.png"));
  run_json["elapsed_s"] = elapsed();
  write_file_atomic(opt.out / "run.json", run_json.dump(2) + "\n");

  report += fmt::format(
      "# minigolf reproduce{}: thesis chapter 6 on the simulated WAM\n\n"
      "Revision `{}`, seed {}, {} threads, {:.0f} s. Everything below was measured by this run on "
      "the full "
      "system (the arm hits the ball in MuJoCo), except the columns marked **thesis**, which quote "
      "Kronander's tables for comparison only. Raw numbers: `csv/`; settings: `run.json`.\n\n",
      opt.quick ? " --quick" : "", opt.revision, opt.seed, system::thread_count(opt.threads),
      elapsed());
  report +=
      "## Data sets (teacher, thesis 5.1)\n\n| field | region (outputs) | examples | strategy | "
      "full-system putts | ball-only putts |\n|---|---|---|---|---|---|\n" +
      data_md;
  report +=
      "\n## Validation MSE (thesis tables 6.1-6.4)\n\nAngle MSE in deg² (the thesis does not state "
      "its unit; its values fit deg²), speed in (m/s)². Arctan: the mean over " +
      std::to_string(arctan_splits) +
      " random training sets, 9 validation points each, corners always in training (thesis 6.2.4); "
      "the other fields: a separate validation set of " +
      std::to_string(kValidationSituations) +
      " random situations collected by the teacher.\n\n| field | output | method | ours | thesis "
      "|\n|---|---|---|---|---|\n" +
      mse_md;
  report +=
      "\n## The robot plays (thesis table 6.5)\n\nRandom test situations of each field's region "
      "(the first 30 are the thesis's attempt count), "
      "hit with the model's prediction on the full system. Oracle ceiling: the fraction of the "
      "same situations for which the teacher finds a sinking putt.\n\n"
      "| field | method | situations | sunk | success (95 % CI) | oracle ceiling | thesis "
      "|\n|---|---|---|---|---|---|---|\n" +
      success_md;
  report += "\n![success](figures/success.png)\n";
  report += fmt::format(
                "\n## Learning curves (beyond the thesis)\n\nSuccess on {} test situations against "
                "the number of training examples (random subsets of the training set; median and "
                "10-90 % over {} subsets).\n\n| field | method | examples | median success | 10-90 "
                "% |\n|---|---|---|---|---|\n",
                curve_situations, curve_seeds) +
            curves_md;
  for (const auto& name : opt.fields)
    report += fmt::format("![{} learning curve](figures/{}_learning_curve.png)\n", name, name);
  if (opt.beyond) {
    report += fmt::format(
        "\n## Beyond the thesis: the robot teaches itself\n\n"
        "No teacher, no data set: `minigolf self-teach` chooses its own putts on the full system "
        "and learns from every "
        "outcome, misses included, through hindsight labels (where each ball path says other holes "
        "would have been sunk). "
        "Baselines in the same simulator, on the same test situations, with the same accounting: "
        "**teacher-gpr** is the "
        "thesis protocol (the teacher collects examples at random situations, every full-system "
        "putt it spends counted; "
        "GPR on what it found so far), **crkr** is Cost-regularized Kernel Regression (Kober et "
        "al. 2012). "
        "Success against own full-system putts, median and 10-90 % over {} runs, {} test "
        "situations per point.\n\n"
        "| field | learner | own putts | median success | 10-90 % |\n|---|---|---|---|---|\n",
        opt.quick ? 2 : 10, opt.quick ? 30 : 100);
    report += beyond_md["curves"];
    report += fmt::format(
                  "\n### Goal check: one self-taught robot (seed {}) on {} test situations\n\n"
                  "| field | own putts | situations | sunk | success (95 % CI) "
                  "|\n|---|---|---|---|---|\n",
                  opt.seed, n_test) +
              beyond_md["goal"];
    report +=
        "\n### Hindsight labels replayed with the hole really there\n\nOwn-target checks: labels "
        "within 1 cm of the target of "
        "the putt they came from, checked by that putt's outcome (free). Replayed: labels more "
        "than 2 cm from it, replayed on "
        "the full system with the hole at the label.\n\n"
        "| field | putts | labels | own-target checks sank | replayed | precision (95 % CI) "
        "|\n|---|---|---|---|---|---|\n" +
        beyond_md["hindsight"];
    report += fmt::format(
                  "\n### Noise\n\nPerception: the hole's and the ball's perceived positions each "
                  "off by a Gaussian of this "
                  "std per axis (the robot chooses its putt for the xi it sees). Execution: the "
                  "launch study's joint-torque "
                  "noise. {} test situations per point.\n\n"
                  "| field | model | noise | level | success (95 % CI) |\n|---|---|---|---|---|\n",
                  opt.quick ? 30 : 100) +
              beyond_md["noise"];
    report += "\n" + beyond_md["figures"];
  }
  if (!real_md["rows"].empty()) {
    report += fmt::format(
        "\n## The real-robot rows (beyond the thesis: a plant stands in for the real WAM)\n\n"
        "The thesis played 10 attempts per model on its real arm (table 6.5). Here the plant `{}` "
        "(hash {}; grass, "
        "a missed tilt, a biased club face, a slower arm, friction, vision noise and latency: "
        "docs/reality.md) is the "
        "real arm: the nominal-simulator model as it is, then after 10 of the robot's own putts "
        "there "
        "(`self-teach --prior`, a residual over the model). The oracle ceiling is the teacher's "
        "under the plant on the "
        "same 10 situations.\n\n"
        "| field | method | nominal model | adapted by 10 own putts | oracle ceiling | thesis real "
        "robot (for comparison) |\n"
        "|---|---|---|---|---|---|\n",
        real_plant.source, real_plant.hash);
    report += real_md["rows"];
    report +=
        "\n### Adaptation curves over random plants (`plant random`)\n\nThe GPR nominal model on "
        "seeded random plants; "
        "success after that many own putts (0: the nominal model), and its ratio to each plant's "
        "oracle ceiling.\n\n"
        "| field | own putts | median | 10-90 % | worst | of ceiling: median | worst | plants at "
        ">= 95 % of ceiling |\n"
        "|---|---|---|---|---|---|---|---|\n" +
        real_md["curves"] + "\n" + real_md["figures"];
  }
  report += rounds_md;
  report += "\n## Figures\n\n" + figures_md;
  write_file_atomic(opt.out / "report.md", report);
  say(fmt::format("report written to {}", (opt.out / "report.md").string()));
}

}  // namespace mg::experiments
