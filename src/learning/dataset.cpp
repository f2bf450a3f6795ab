#include "learning/dataset.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "core/error.hpp"

namespace mg::learning {
namespace {

Eigen::MatrixXd pick_columns(const CsvTable& table, const std::vector<std::string>& names) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(table.num_rows()),
                    static_cast<Eigen::Index>(names.size()));
  for (std::size_t j = 0; j < names.size(); ++j) {
    const std::size_t c = table.column_index(names[j]);
    for (std::size_t i = 0; i < table.num_rows(); ++i)
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = table.rows[i][c];
  }
  return m;
}

void check_names(const std::string& source, const std::vector<std::string>& names,
                 const char* what) {
  if (names.empty())
    throw InputError(
        fmt::format("{}: {} columns: expected at least one name, got none", source, what));
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = i + 1; j < names.size(); ++j)
      if (names[i] == names[j])
        throw InputError(fmt::format("{}: column '{}' is named twice", source, names[i]));
}

}  // namespace

std::vector<std::pair<std::string, double>> constant_columns(
    const CsvTable& table, const std::vector<std::string>& candidates,
    const std::vector<std::string>& used) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& name : candidates) {
    if (std::find(used.begin(), used.end(), name) != used.end()) continue;
    const auto it = std::find(table.header.begin(), table.header.end(), name);
    if (it == table.header.end() || table.rows.empty()) continue;
    const auto c = static_cast<std::size_t>(it - table.header.begin());
    const double v = table.rows.front()[c];
    bool constant = true;
    for (const auto& row : table.rows) constant = constant && row[c] == v;
    if (constant) out.emplace_back(name, v);
  }
  return out;
}

Dataset dataset_from_table(const CsvTable& table, const std::vector<std::string>& input_names,
                           const std::vector<std::string>& output_names, int min_rows) {
  check_names(table.source, input_names, "input");
  check_names(table.source, output_names, "output");
  for (const auto& n : input_names)
    if (std::find(output_names.begin(), output_names.end(), n) != output_names.end())
      throw InputError(
          fmt::format("{}: column '{}' is both an input and an output", table.source, n));
  Dataset d;
  d.source = table.source;
  d.input_names = input_names;
  d.output_names = output_names;
  d.inputs = pick_columns(table, input_names);
  d.outputs = pick_columns(table, output_names);
  // Situations and hitting parameters are metres, radians and m/s: a value beyond 1e100 is a
  // broken file, and squaring it (variances, distances) would overflow to inf.
  for (const auto* m : {&d.inputs, &d.outputs})
    for (Eigen::Index i = 0; i < m->rows(); ++i)
      for (Eigen::Index j = 0; j < m->cols(); ++j)
        if (std::abs((*m)(i, j)) > kMaxDatasetValue)
          throw InputError(fmt::format("{}: row {}, column '{}': {:g} is beyond +-{:g}",
                                       table.source, i + 1,
                                       m == &d.inputs ? input_names[static_cast<std::size_t>(j)]
                                                      : output_names[static_cast<std::size_t>(j)],
                                       (*m)(i, j), kMaxDatasetValue));
  if (d.size() < min_rows)
    throw InputError(fmt::format("{}: expected at least {} data rows, got {}", table.source,
                                 min_rows, d.size()));
  return d;
}

Dataset load_dataset(const std::filesystem::path& path, const std::vector<std::string>& input_names,
                     const std::vector<std::string>& output_names) {
  return dataset_from_table(read_csv(path), input_names, output_names, 2);
}

Eigen::MatrixXd query_inputs(const CsvTable& table, const std::vector<std::string>& input_names) {
  Eigen::MatrixXd m = pick_columns(table, input_names);
  if (m.rows() < 1)
    throw InputError(fmt::format("{}: expected at least 1 query row, got 0", table.source));
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      if (std::abs(m(i, j)) > kMaxDatasetValue)
        throw InputError(fmt::format("{}: row {}, column '{}': {:g} is beyond +-{:g}", table.source,
                                     i + 1, input_names[static_cast<std::size_t>(j)], m(i, j),
                                     kMaxDatasetValue));
  return m;
}

}  // namespace mg::learning
