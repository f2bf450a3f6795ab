#pragma once
/// Datasets of the hitting-parameter learners: CSV with a header, inputs and outputs chosen by
/// column name (defaults: inputs `xi_x,xi_y` [m], outputs `angle` [rad], `speed` [m/s]).
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/csv.hpp"

namespace mg::learning {

inline const std::vector<std::string> kDefaultInputs{"xi_x", "xi_y"};
inline const std::vector<std::string> kDefaultOutputs{"angle", "speed"};

struct Dataset {
  std::string source;                     ///< file name, for messages
  std::vector<std::string> input_names;   ///< (I)
  std::vector<std::string> output_names;  ///< (O)
  Eigen::MatrixXd inputs;                 ///< (N x I), one sample per row
  Eigen::MatrixXd outputs;                ///< (N x O)
  int size() const { return static_cast<int>(inputs.rows()); }
};

/// Of the columns `candidates` (e.g. "speed"), those present in `table`, not among `used` (the
/// model's inputs and outputs), and constant over every row: (name, value) pairs. An angle-only
/// data set records its fixed club speed this way (Model::fixed).
std::vector<std::pair<std::string, double>> constant_columns(
    const CsvTable& table, const std::vector<std::string>& candidates,
    const std::vector<std::string>& used);

/// Largest magnitude a data set value may have (larger ones are an InputError).
inline constexpr double kMaxDatasetValue = 1e100;

/// Picks the named columns of a parsed CSV table. Throws `mg::InputError` naming the source when a
/// column is missing, a name is used twice, or there are fewer than `min_rows` rows.
Dataset dataset_from_table(const CsvTable& table, const std::vector<std::string>& input_names,
                           const std::vector<std::string>& output_names, int min_rows = 2);

/// Reads a training/validation dataset (at least 2 rows).
Dataset load_dataset(const std::filesystem::path& path,
                     const std::vector<std::string>& input_names = kDefaultInputs,
                     const std::vector<std::string>& output_names = kDefaultOutputs);

/// The named input columns of a query table (at least 1 row), (N x I).
Eigen::MatrixXd query_inputs(const CsvTable& table, const std::vector<std::string>& input_names);

}  // namespace mg::learning
