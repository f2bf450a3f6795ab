#pragma once
/// Numeric CSV tables with a header row (the format of datasets, demonstrations, trajectories).
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace mg {

/// A numeric table: named columns, rows of finite doubles.
struct CsvTable {
  std::string source;               ///< where it came from, for error messages
  std::vector<std::string> header;  ///< column names, in file order
  std::vector<std::vector<double>> rows;

  /// Index of the column `name`; throws `InputError` naming the source and the column.
  std::size_t column_index(std::string_view name) const;
  /// Copy of one column by name.
  std::vector<double> column(std::string_view name) const;
  std::size_t num_rows() const { return rows.size(); }
};

/// Parses CSV text with a header. Every cell must be a finite number; blank lines are skipped;
/// `#` starts a comment line. Throws `InputError` with source, line and column on any problem.
CsvTable parse_csv(std::string_view text, std::string_view source);

/// Reads and parses a CSV file (see `parse_csv`).
CsvTable read_csv(const std::filesystem::path& path);

/// Formats a table as CSV text; numbers in shortest round-trip form.
std::string format_csv(const std::vector<std::string>& header,
                       const std::vector<std::vector<double>>& rows);

}  // namespace mg
