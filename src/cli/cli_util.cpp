#include "cli/cli_util.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "belief/belief.hpp"
#include "core/error.hpp"
#include "core/io.hpp"

namespace mg::cli {

CLI::Validator finite_number(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0.0;
        const char* first = text.data() + (!text.empty() && text.front() == '+' ? 1 : 0);
        auto [ptr, ec] = std::from_chars(first, text.data() + text.size(), v);
        if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
            !std::isfinite(v) || v < lo || v > hi)
          return fmt::format("expected a finite number in [{}, {}], got '{}'", lo, hi, text);
        return {};
      },
      fmt::format("NUMBER in [{}, {}]", lo, hi));
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        const char* first = text.data() + (!text.empty() && text.front() == '+' ? 1 : 0);
        auto [ptr, ec] = std::from_chars(first, text.data() + text.size(), v);
        if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() ||
            !std::isfinite(v))
          return fmt::format("expected a finite number, got '{}'", text);
        return {};
      },
      "NUMBER");
}

CLI::Validator any_name() {
  return CLI::Validator([](std::string&) { return std::string(); }, "NAME");
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    items.push_back(text.substr(start, comma == std::string::npos ? comma : comma - start));
    if (comma == std::string::npos) return items;
    start = comma + 1;
  }
}

CLI::Validator list_of(const CLI::Validator& element) {
  return CLI::Validator(
      [element](std::string& text) -> std::string {
        for (std::string item : split_list(text)) {
          if (item.empty()) return fmt::format("empty element in the list '{}'", text);
          if (std::string error = element(item); !error.empty()) return error;
        }
        return {};
      },
      element.get_description() + ",...");
}

CLI::Validator output_file() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        try {
          check_output_file(path);
        } catch (const Error& e) {
          return e.what();
        }
        return {};
      },
      "FILE");
}

void refuse_empty_values(CLI::App& app) {
  const CLI::Validator non_empty(
      [](std::string& text) -> std::string {
        return text.empty() ? "expected a value, got an empty one ('')" : "";
      },
      "");
  for (CLI::Option* opt : app.get_options())
    if (opt->get_type_size_max() > 0)
      opt->transform(non_empty);  // first: its message, not a later validator's, is the one given
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    refuse_empty_values(*sub);
}

std::string one_line(std::string_view text, std::size_t max) {
  std::string out;
  out.reserve(std::min(text.size(), max + 40));
  const auto add = [&](std::string_view part) {
    for (unsigned char c : part) out += c < 0x20 || c == 0x7f ? '?' : static_cast<char>(c);
  };
  if (text.size() <= max) {
    add(text);
  } else {
    add(text.substr(0, max / 2));
    out += fmt::format(" ... ({} characters) ... ", text.size());
    add(text.substr(text.size() - max / 4));
  }
  return out;
}

CLI::Validator unsigned_integer(std::uint64_t hi) {
  return CLI::Validator(
      [hi](std::string& text) -> std::string {
        std::uint64_t v = 0;
        auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || v > hi)
          return fmt::format("expected an integer in [0, {}], got '{}'", hi, text);
        return {};
      },
      fmt::format("INTEGER in [0, {}]", hi));
}

double parse_number(const std::string& what, const std::string& text) {
  double v = 0.0;
  const char* first = text.data();
  if (!text.empty() && text.front() == '+') ++first;
  auto [ptr, ec] = std::from_chars(first, text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size())
    throw InputError(fmt::format("{}: expected a number, got '{}'", what, text));
  if (!std::isfinite(v))
    throw InputError(fmt::format("{}: expected a finite number, got '{}'", what, text));
  return v;
}

std::uint64_t parse_unsigned(const std::string& what, const std::string& text) {
  std::uint64_t v = 0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size())
    throw InputError(fmt::format("{}: expected a non-negative integer, got '{}'", what, text));
  return v;
}

template <std::size_t N>
std::array<double, N> parse_vector(const std::string& what, const std::string& text) {
  std::array<double, N> out{};
  std::size_t start = 0;
  for (std::size_t i = 0; i < N; ++i) {
    const std::size_t comma = text.find(',', start);
    const bool last = i + 1 == N;
    if (last != (comma == std::string::npos))
      throw InputError(
          fmt::format("{}: expected {} comma-separated numbers, got '{}'", what, N, text));
    out[i] = parse_number(what, text.substr(start, last ? std::string::npos : comma - start));
    start = comma + 1;
  }
  return out;
}

template std::array<double, 2> parse_vector<2>(const std::string&, const std::string&);
template std::array<double, 3> parse_vector<3>(const std::string&, const std::string&);
template std::array<double, 5> parse_vector<5>(const std::string&, const std::string&);

plant::Plant load_plant_arg(const std::string& path) {
  if (path.empty()) return {};
  return plant::load_plant(path);
}

plant::Plant load_belief_arg(const std::string& path) {
  if (path.empty()) return {};
  return belief::load_belief(path).estimate;
}

nlohmann::json plant_json(const plant::Plant& plant) {
  if (plant.source.empty()) return nullptr;
  return {{"path", plant.source}, {"hash", plant.hash}};
}

std::filesystem::path frames_dir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir, ec))
    throw InputError(fmt::format("--frames: '{}': cannot make this folder", dir));
  return dir;
}

}  // namespace mg::cli
