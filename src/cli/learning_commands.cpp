// train | predict | validate: thin wrappers over mg::learning (parse, load, call, print).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/cli_util.hpp"
#include "cli/commands.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/io.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"

namespace mg::cli {
namespace {

const learning::TrainOptions kTrainDefaults{};  // the library's defaults, in one place

struct LearnArgs {
  std::string method = std::string(learning::method_name(kTrainDefaults.method));
  std::vector<std::string> inputs = learning::kDefaultInputs;
  std::vector<std::string> outputs = learning::kDefaultOutputs;
  int gaussians = kTrainDefaults.num_gaussians;
  std::string select = std::string(learning::selection_name(kTrainDefaults.selection));
  int max_gaussians = kTrainDefaults.max_gaussians;
  int restarts = kTrainDefaults.restarts;
  std::uint64_t seed = kTrainDefaults.seed;
  double reg_covar = kTrainDefaults.em.reg_covar;
  CLI::Option* reg_covar_option =
      nullptr;  ///< given: use reg_covar as is; else chosen by cross-validation
  std::vector<double> length_scales, signal_std, noise_std;
  std::string length_scale_bounds, signal_std_bounds, noise_std_bounds;
  bool no_optimize = false;
  bool json = false;
};

std::array<double, 2> parse_bounds(const std::string& what, const std::string& text) {
  if (text.empty()) return {0.0, 0.0};
  const auto v = parse_vector<2>(what, text);
  if (!(v[0] > 0.0) || !(v[1] >= v[0]))
    throw InputError(fmt::format("{}: expected 0 < lower <= upper, got '{}'", what, text));
  return v;
}

void add_learn_options(CLI::App* cmd, LearnArgs& a) {
  cmd->add_option("--method", a.method, "gpr | gmr | joint-gmr")->capture_default_str();
  add_list_option(cmd, "--inputs", a.inputs, "Input columns, comma-separated", any_name());
  add_list_option(cmd, "--outputs", a.outputs, "Output columns, comma-separated", any_name());
  cmd->add_option("--gaussians", a.gaussians, "Number of Gaussians (GMR); 0 = choose by --select")
      ->capture_default_str();
  cmd->add_option("--select", a.select, "How to choose the number of Gaussians: bic | cv")
      ->capture_default_str();
  cmd->add_option("--max-gaussians", a.max_gaussians,
                  "Largest number of Gaussians tried by --select")
      ->capture_default_str();
  cmd->add_option("--restarts", a.restarts, "GPR optimiser starts / k-means++ seedings")
      ->capture_default_str();
  cmd->add_option("--seed", a.seed, "Random seed")
      ->check(unsigned_integer())
      ->capture_default_str();
  a.reg_covar_option = cmd->add_option("--reg-covar", a.reg_covar,
                                       "GMM covariance regularisation (standardised units, > 0); "
                                       "default: chosen from 1e-6..1e-1 by cross-validation");
  add_list_option(cmd, "--length-scales", a.length_scales,
                  "GPR initial length scales: one, or one per input (comma-separated)",
                  finite_number());
  add_list_option(cmd, "--signal-std", a.signal_std,
                  "GPR initial signal std: one, or one per output (output units, comma-separated)",
                  finite_number());
  add_list_option(cmd, "--noise-std", a.noise_std,
                  "GPR initial noise std: one, or one per output (output units, comma-separated)",
                  finite_number());
  cmd->add_option("--length-scale-bounds", a.length_scale_bounds,
                  "GPR length scale bounds LO,HI (input units)");
  cmd->add_option("--signal-std-bounds", a.signal_std_bounds,
                  "GPR signal std bounds LO,HI (output units)");
  cmd->add_option("--noise-std-bounds", a.noise_std_bounds,
                  "GPR noise std bounds LO,HI (output units)");
  cmd->add_flag("--no-optimize", a.no_optimize, "GPR: use the initial hyperparameters as they are");
  cmd->add_flag("--json", a.json, "Print one JSON object");
}

learning::TrainOptions make_train_options(const LearnArgs& a, std::size_t num_inputs,
                                          std::size_t num_outputs) {
  learning::TrainOptions o;
  o.method = learning::parse_method(a.method);
  o.num_gaussians = a.gaussians;
  o.selection = learning::parse_selection(a.select);
  o.max_gaussians = a.max_gaussians;
  o.restarts = a.restarts;
  o.seed = a.seed;
  o.em.reg_covar = a.reg_covar;
  o.choose_reg_covar = a.reg_covar_option == nullptr || a.reg_covar_option->count() == 0;
  auto per_output = [&](const std::string& what, const std::vector<double>& v) {
    if (!v.empty() && v.size() != 1 && v.size() != num_outputs)
      throw InputError(fmt::format("{}: expected 1 or {} values (one per output), got {}", what,
                                   num_outputs, v.size()));
    for (double x : v)
      if (!(x > 0.0))
        throw InputError(fmt::format("{}: expected positive numbers, got {}", what, x));
    return v;
  };
  const std::vector<double> sf = per_output("--signal-std", a.signal_std);
  const std::vector<double> sn = per_output("--noise-std", a.noise_std);
  const std::vector<double>& ls = a.length_scales;
  if (!ls.empty() && ls.size() != 1 && ls.size() != num_inputs)
    throw InputError(fmt::format("--length-scales: expected 1 or {} values (one per input), got {}",
                                 num_inputs, ls.size()));
  stats::GprOptions base;
  base.initial_length_scales =
      Eigen::Map<const Eigen::VectorXd>(ls.data(), static_cast<Eigen::Index>(ls.size()));
  base.length_scale_bounds = parse_bounds("--length-scale-bounds", a.length_scale_bounds);
  base.signal_std_bounds = parse_bounds("--signal-std-bounds", a.signal_std_bounds);
  base.noise_std_bounds = parse_bounds("--noise-std-bounds", a.noise_std_bounds);
  base.optimize = !a.no_optimize;
  for (std::size_t i = 0; i < num_outputs; ++i) {
    stats::GprOptions g = base;
    if (!sf.empty()) g.initial_signal_std = sf.size() == 1 ? sf[0] : sf[i];
    if (!sn.empty()) g.initial_noise_std = sn.size() == 1 ? sn[0] : sn[i];
    o.gpr.push_back(g);
  }
  return o;
}

std::string fmt_vec(const Eigen::VectorXd& v) {
  std::vector<std::string> s;
  for (Eigen::Index i = 0; i < v.size(); ++i) s.push_back(fmt::format("{:.6g}", v(i)));
  return fmt::format("{}", fmt::join(s, ", "));
}

}  // namespace

void add_learning_commands(CLI::App& app) {
  // ---- train
  struct TrainArgs {
    LearnArgs learn;
    std::string data;
    std::string model;
  };
  auto t = std::make_shared<TrainArgs>();
  CLI::App* train = app.add_subcommand(
      "train", "Train a hitting-parameter learner (xi -> angle, speed) on a CSV dataset");
  train->add_option("data", t->data, "Training dataset (CSV with a header)")->required();
  train->add_option("-o,--output", t->model, "Model file to write (JSON)")
      ->check(output_file())
      ->required();
  add_learn_options(train, t->learn);
  train->callback([t] {
    const auto& inputs = t->learn.inputs;
    const auto& outputs = t->learn.outputs;
    const learning::TrainOptions opt = make_train_options(t->learn, inputs.size(), outputs.size());
    const CsvTable table = read_csv(t->data);
    const learning::Dataset data = learning::dataset_from_table(table, inputs, outputs);
    learning::Model model = learning::train(data, opt);
    std::vector<std::string> used = inputs;
    used.insert(used.end(), outputs.begin(), outputs.end());
    model.fixed = learning::constant_columns(table, {"speed"}, used);  // angle-only data sets
    learning::save_model(model, t->model);
    if (t->learn.json) {
      fmt::print("{}\n", learning::report_to_json(model).dump());
      return;
    }
    fmt::print("trained {} on {} rows of {} ({} -> {}); model written to {}\n",
               learning::method_name(model.method), data.size(), data.source,
               fmt::join(inputs, ","), fmt::join(outputs, ","), t->model);
    for (int o = 0; o < model.num_outputs(); ++o) {
      const auto& r = model.reports[static_cast<std::size_t>(o)];
      if (model.method == learning::Method::kGpr)
        fmt::print(
            "  {:<10} length scales [{}], signal std {:.6g}, noise std {:.6g}, log marginal "
            "likelihood {:.6g}\n",
            outputs[static_cast<std::size_t>(o)], fmt_vec(r.length_scales), r.signal_std,
            r.noise_std, r.log_marginal_likelihood);
      else
        fmt::print("  {:<10} {} Gaussians, log-likelihood {:.6g}, BIC {:.6g}\n",
                   outputs[static_cast<std::size_t>(o)], r.n_gaussians, r.log_likelihood, r.bic);
    }
  });

  // ---- predict
  struct PredictArgs {
    std::string model;
    std::string queries;
  };
  auto p = std::make_shared<PredictArgs>();
  CLI::App* predict = app.add_subcommand(
      "predict", "Predict hitting parameters (mean and std per output) for query situations");
  predict->add_option("model", p->model, "Model file written by 'train'")->required();
  predict
      ->add_option("queries", p->queries,
                   "CSV with the model's input columns (other columns are echoed)")
      ->required();
  predict->callback([p] {
    const learning::Model model = learning::load_model(p->model);
    const CsvTable table = read_csv(p->queries);
    const Eigen::MatrixXd x = learning::query_inputs(table, model.input_names);
    const learning::Predictions pred = learning::predict(model, x);
    std::vector<std::string> header = table.header;
    for (const auto& name : model.output_names) {
      header.push_back(name + "_mean");
      header.push_back(name + "_std");
    }
    std::vector<std::vector<double>> rows;
    for (std::size_t i = 0; i < table.num_rows(); ++i) {
      std::vector<double> row = table.rows[i];
      for (int o = 0; o < model.num_outputs(); ++o) {
        row.push_back(pred.mean(static_cast<Eigen::Index>(i), o));
        row.push_back(pred.std(static_cast<Eigen::Index>(i), o));
      }
      rows.push_back(std::move(row));
    }
    fmt::print("{}", format_csv(header, rows));
    // Flagged, not hidden: GMR's linear extrapolation can ask for any value far from its data.
    if (const auto far = learning::beyond_training(model, pred); !far.empty()) {
      const auto& w = *std::max_element(far.begin(), far.end(),
                                        [](auto& a, auto& b) { return a.spread < b.spread; });
      fmt::print(stderr,
                 "minigolf: warning: {} prediction(s) lie more than {:g} training standard "
                 "deviations from "
                 "the training outputs (worst: row {}, {} at {:.3g} stds): queries far outside the "
                 "training inputs\n",
                 far.size(), learning::kMaxPredictionSpread, w.row + 1,
                 model.output_names[static_cast<std::size_t>(w.output)], w.spread);
    }
  });

  // ---- validate
  struct ValidateArgs {
    LearnArgs learn;
    std::string train;
    std::string validate;
    std::string model;
  };
  auto v = std::make_shared<ValidateArgs>();
  CLI::App* validate = app.add_subcommand(
      "validate",
      "Train on one dataset and report MSE and NLPD per output on another (thesis Definition 6.1)");
  validate->add_option("--train", v->train, "Training dataset (CSV)")->required();
  validate->add_option("--validate", v->validate, "Validation dataset (CSV)")->required();
  validate->add_option("-o,--output", v->model, "Also write the trained model here")
      ->check(output_file());
  add_learn_options(validate, v->learn);
  validate->callback([v] {
    const auto& inputs = v->learn.inputs;
    const auto& outputs = v->learn.outputs;
    const learning::TrainOptions opt = make_train_options(v->learn, inputs.size(), outputs.size());
    const learning::Dataset train_data = learning::load_dataset(v->train, inputs, outputs);
    const learning::Dataset val_data = learning::load_dataset(v->validate, inputs, outputs);
    const learning::Model model = learning::train(train_data, opt);
    if (!v->model.empty()) learning::save_model(model, v->model);
    const std::vector<learning::Score> scores = learning::score(model, val_data);
    if (v->learn.json) {
      nlohmann::json j = nlohmann::json::object();
      for (std::size_t o = 0; o < outputs.size(); ++o)
        j[outputs[o]] = {{"mse", scores[o].mse}, {"nlpd", scores[o].nlpd}};
      fmt::print("{}\n", j.dump());
      return;
    }
    fmt::print("{} trained on {} rows, validated on {} rows\n", learning::method_name(model.method),
               train_data.size(), val_data.size());
    fmt::print("{:<12} {:>14} {:>14}\n", "output", "mse", "nlpd");
    for (std::size_t o = 0; o < outputs.size(); ++o)
      fmt::print("{:<12} {:>14.6g} {:>14.6g}\n", outputs[o], scores[o].mse, scores[o].nlpd);
  });
}

}  // namespace mg::cli
