#include "core/csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"

namespace mg {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return cells;
}

}  // namespace

std::size_t CsvTable::column_index(std::string_view name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end())
    throw InputError(
        fmt::format("{}: missing column '{}' (columns: {})", source, name, fmt::join(header, ",")));
  return static_cast<std::size_t>(it - header.begin());
}

std::vector<double> CsvTable::column(std::string_view name) const {
  const std::size_t j = column_index(name);
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(row[j]);
  return out;
}

CsvTable parse_csv(std::string_view text, std::string_view source) {
  CsvTable table;
  table.source = std::string(source);
  std::size_t line_no = 0;
  std::size_t pos = 0;
  bool have_header = false;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = trim(text.substr(pos, end - pos));
    pos = end + 1;
    ++line_no;
    if (line.empty() || line.front() == '#') {
      if (end == text.size()) break;
      continue;
    }
    auto cells = split_cells(line);
    if (!have_header) {
      for (auto c : cells) {
        if (c.empty())
          throw InputError(fmt::format("{}:{}: empty column name in header", source, line_no));
        if (std::find(table.header.begin(), table.header.end(), c) != table.header.end())
          throw InputError(fmt::format("{}:{}: duplicate column '{}'", source, line_no, c));
        table.header.emplace_back(c);
      }
      have_header = true;
    } else {
      if (cells.size() != table.header.size())
        throw InputError(fmt::format("{}:{}: expected {} values, got {}", source, line_no,
                                     table.header.size(), cells.size()));
      std::vector<double> row(cells.size());
      for (std::size_t j = 0; j < cells.size(); ++j) {
        const std::string_view c = cells[j];
        double v = 0.0;
        const char* first = c.data();
        if (!c.empty() && c.front() == '+') ++first;
        auto [ptr, ec] = std::from_chars(first, c.data() + c.size(), v);
        if (c.empty() || ec != std::errc() || ptr != c.data() + c.size())
          throw InputError(fmt::format("{}:{}: column '{}': expected a number, got '{}'", source,
                                       line_no, table.header[j], c));
        if (!std::isfinite(v))
          throw InputError(fmt::format("{}:{}: column '{}': expected a finite number, got '{}'",
                                       source, line_no, table.header[j], c));
        row[j] = v;
      }
      table.rows.push_back(std::move(row));
    }
    if (end == text.size()) break;
  }
  if (!have_header) throw InputError(fmt::format("{}: empty file, expected a header row", source));
  return table;
}

CsvTable read_csv(const std::filesystem::path& path) {
  return parse_csv(read_text_file(path), path.string());
}

std::string format_csv(const std::vector<std::string>& header,
                       const std::vector<std::vector<double>>& rows) {
  std::string out = fmt::format("{}\n", fmt::join(header, ","));
  for (const auto& row : rows) {
    for (std::size_t j = 0; j < row.size(); ++j) {
      if (j) out += ',';
      out += format_exact(row[j]);
    }
    out += '\n';
  }
  return out;
}

}  // namespace mg
