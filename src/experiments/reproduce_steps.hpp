#pragma once
/// The steps of `reproduce` (reproduce.hpp) and what they share. Not a public interface: the
/// run's settings and helpers (Run), the tables the steps fill (Tables), one field's data
/// (FieldRun). reproduce.cpp runs the steps in order; each step is one job:
///   prepare_field         data sets (shipped or collected), training / validation split
///   validate_models       training, validation MSE (tables 6.1-6.4)       reproduce_field.cpp
///   play_test_situations  the robot plays, the oracle ceiling (table 6.5)  reproduce_field.cpp
///   learning_curves       success against training examples               reproduce_field.cpp
///   field_figures         predictions, data set, field, sinking window     reproduce_figures.cpp
///   report_markdown       report.md from the tables                        reproduce_report.cpp
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include "core/csv.hpp"
#include "experiments/reproduce.hpp"
#include "field/situations.hpp"
#include "learning/dataset.hpp"
#include "learning/learner.hpp"
#include "plant/plant.hpp"
#include "system/system.hpp"
#include "teacher/teacher.hpp"

namespace mg::experiments::reproduce_steps {

/// Regions with at least this many collection points use the thesis's arctan protocol (random
/// validation points from the data set); smaller ones a separate validation set.
inline constexpr int kSplitMinPoints = 24;
/// Situations of a separate validation set.
inline constexpr int kValidationSituations = 10;
/// [deg/rad]
inline constexpr double kDeg = 180.0 / 3.14159265358979323846;

/// The thesis's chapter-6 values (data/reference/thesis-results.yaml), for the "thesis" columns.
struct Thesis {
  YAML::Node root;
  /// MSE of (field, output, method) as printed, or NaN.
  double mse(const std::string& field, const std::string& output, const std::string& method) const;
  /// Success ratio of (field, method) `where` ("simulator" | "real_robot"), or NaN.
  double success(const std::string& field, const std::string& method,
                 const char* where = "simulator") const;
};
/// Throws InputError naming the file if it is malformed.
Thesis load_thesis();

/// What every step reads: the options, the sizes of this run, where files go, progress, plots.
struct Run {
  explicit Run(const ReproduceOptions& options) : opt(options) {}
  const ReproduceOptions& opt;
  Thesis thesis;
  std::filesystem::path datasets;  ///< folder of the data sets read
  int n_test = 0;                  ///< test situations per field
  int curve_seeds = 0;             ///< random subsets per learning-curve point
  int curve_situations = 30;       ///< test situations per learning-curve point
  int arctan_splits = 0;           ///< random training sets of the arctan protocol
  plant::Plant run_plant;          ///< every putt happens in it (empty: the robot's model)
  plant::Plant run_belief;         ///< what the robot believes of it (empty: its field files)
  plant::Plant real_plant;         ///< stands in for the real WAM
  std::function<void(const std::string&)> say;                       ///< a progress line
  std::function<void(const std::string&, const std::string&)> plot;  ///< plot.py args, PNG
  std::function<std::string(const std::string&)> csv_path;           ///< file name -> out/csv/...
  std::function<std::string(const std::string&)> fig_path;  ///< file name -> out/figures/...
};

/// What the steps write: Markdown table rows by table, the success CSV, the run's JSON.
struct Tables {
  std::string mse_md, success_md, curves_md, data_md, figures_md;
  std::map<std::string, std::string> beyond_md, real_md;
  std::string success_csv =
      "field,method,situations,sunk,success_ratio,ci_lo,ci_hi,oracle_ceiling,thesis_ratio\n";
};

/// Everything about one field's run.
struct FieldRun {
  std::string name;
  std::unique_ptr<system::System> sys;
  field::Situations region;
  std::filesystem::path data_file;  ///< the data set read
  CsvTable table;                   ///< the data set as read
  std::vector<double> index;        ///< its "index" column
  learning::Dataset all;            ///< every example
  std::vector<std::string> inputs, outputs, methods;
  bool split = false;                   ///< arctan protocol
  learning::Dataset train, validation;  ///< the thesis's training / validation sets
  std::vector<std::pair<std::string, double>> fixed;
  teacher::TeacherOptions teacher;
};

/// The rows `rows` of `d`.
learning::Dataset subset(const learning::Dataset& d, const std::vector<int>& rows);
/// The training options of `method` on `field` for `n` examples (thesis 6.2.1: two Gaussians on
/// flat).
learning::TrainOptions train_options(const std::string& method, const std::string& field, int n,
                                     std::uint64_t seed);

/// The field's system, data sets (collected with opt.collect) and training / validation split;
/// writes <field>_train.csv and <field>_validation.csv. Adds the data-set row.
FieldRun prepare_field(const Run& run, const std::string& name, Tables& t);
/// Trains every method, saves the models, adds their validation MSE rows; the models by method.
std::map<std::string, learning::Model> validate_models(const Run& run, const FieldRun& f,
                                                       Tables& t);
/// The robot plays run.n_test random test situations with each model (and, on split fields, the
/// models trained on the full data set); the oracle teacher once per situation. Adds the success
/// rows and writes the evaluation CSVs.
void play_test_situations(const Run& run, const FieldRun& f,
                          const std::map<std::string, learning::Model>& models, Tables& t);
/// Success against the number of training examples (random subsets); adds the curve rows.
void learning_curves(const Run& run, const FieldRun& f, Tables& t);
/// The field's figures: model predictions, the data set, the field with ball paths, the sinking
/// window. Adds their links.
void field_figures(const Run& run, const FieldRun& f,
                   const std::map<std::string, learning::Model>& models, Tables& t);
/// report.md from the tables; `rounds_md`: the round-of-minigolf section (may be empty).
std::string report_markdown(const Run& run, const Tables& t, const std::string& rounds_md,
                            double elapsed_s);

}  // namespace mg::experiments::reproduce_steps
