#pragma once
/// Typed reading of YAML maps for the project's data files (fields, plants): every error names
/// the file and the key path, and keys that were not asked about are an error (a typo must not
/// fall back to a default silently). Internal to the parsers (links yaml-cpp).
///
/// `load_yaml` is the one way the project reads YAML text (fields, courses, plants, module
/// configs, the thesis reference): exactly one document, no key twice in a mapping.
#include <array>
#include <cmath>
#include <cstddef>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"

namespace mg::field {

/// Nodes a YAML data file may have at most (aliases can make a short text a huge tree), and how
/// deep its mappings and lists may nest (an alias of an ancestor makes an endless one).
inline constexpr std::size_t kMaxYamlNodes = 1000000;
inline constexpr int kMaxYamlDepth = 64;

namespace detail {

/// The key path of `keys` for a message ("holes[0].par"), shortened when long.
inline std::string yaml_path(const std::vector<std::string>& keys) {
  std::string path;
  for (const auto& k : keys) path += k.front() == '[' || path.empty() ? k : "." + k;
  return path.size() > 200 ? path.substr(0, 200) + "..." : path;
}

/// Throws InputError naming `source` and the key path of the first key given twice in one
/// mapping (yaml-cpp keeps both; `node[key]` finds the first, iteration sees both). `keys`: the
/// path so far; `budget`: the nodes it may still visit.
inline void check_unique_keys(const YAML::Node& node, const std::string& source,
                              std::vector<std::string>& keys, std::size_t& budget) {
  if (budget == 0)
    throw InputError(fmt::format("{}: more than {} YAML nodes (expected a small data file)", source,
                                 kMaxYamlNodes));
  --budget;
  if (static_cast<int>(keys.size()) > kMaxYamlDepth)
    throw InputError(
        fmt::format("{}: {}: nested deeper than {} levels (expected a small data "
                    "file)",
                    source, yaml_path(keys), kMaxYamlDepth));
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      keys.push_back(fmt::format("[{}]", i));
      check_unique_keys(node[i], source, keys, budget);
      keys.pop_back();
    }
  } else if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) continue;  // a complex key: the readers refuse it as unknown
      const std::string& key = kv.first.Scalar();
      keys.push_back(key.empty() ? "''" : key);
      if (!seen.insert(key).second)
        throw InputError(fmt::format("{}: {}: duplicate key (a key may appear once per mapping)",
                                     source, yaml_path(keys)));
      check_unique_keys(kv.second, source, keys, budget);
      keys.pop_back();
    }
  }
}

/// Where each document of a YAML text starts (an event handler that ignores the rest);
/// `stalled` once a document starts where the last one did (the parser makes no progress).
class DocumentStarts : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mark) override {
    stalled = stalled || (started && mark.pos <= pos);
    started = true;
    pos = mark.pos, line = mark.line, column = mark.column;
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}

  bool started = false, stalled = false;
  int pos = 0, line = 0, column = 0;
};

}  // namespace detail

/// Parses YAML text from `source` (named in every message): one document (a second `---`
/// document is an error, not ignored), no key twice in a mapping. An empty text is a null node.
/// Throws InputError "SOURCE: malformed YAML: ..." / "SOURCE: a second YAML document ..." /
/// "SOURCE: KEY.PATH: duplicate key ...".
inline YAML::Node load_yaml(std::string_view text, const std::string& source) {
  const std::string yaml(text);
  YAML::Node root;
  try {
    // Count the documents with the event parser (YAML::LoadAll never returns on "," : its parser
    // starts an empty document at the same place again and again).
    std::stringstream in(yaml);
    YAML::Parser parser(in);
    detail::DocumentStarts starts;
    int documents = 0;
    while (documents < 2 && !starts.stalled && parser.HandleNextDocument(starts)) ++documents;
    if (starts.stalled)
      throw InputError(fmt::format("{}: malformed YAML: nothing readable at line {}, column {}",
                                   source, starts.line + 1, starts.column + 1));
    if (documents > 1)
      throw InputError(
          fmt::format("{}: a second YAML document at line {} (expected one; it would be ignored)",
                      source, starts.line + 1));
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: malformed YAML: {}", source, e.what()));
  }
  if (!root) return root;
  std::size_t budget = kMaxYamlNodes;
  std::vector<std::string> keys;
  detail::check_unique_keys(root, source, keys, budget);
  return root;
}

/// Reads typed values from a YAML map, naming `source` and the key path in every error, and
/// rejecting keys it was not asked about (typos must not silently fall back to defaults).
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string source, std::string path)
      : node_(node), source_(std::move(source)), path_(std::move(path)) {
    if (!node_.IsMap()) fail(path_.empty() ? "the file" : path_, "expected a mapping");
  }

  bool has(const std::string& key) {
    seen_.insert(key);
    return static_cast<bool>(node_[key]);
  }
  YAML::Node require(const std::string& key) {
    if (!has(key)) fail(full(key), "missing (required)");
    return node_[key];
  }
  double number(const std::string& key) { return to_number(require(key), full(key)); }
  double number(const std::string& key, double fallback) {
    return has(key) ? to_number(node_[key], full(key)) : fallback;
  }
  std::string text(const std::string& key, const std::string& fallback) {
    if (!has(key)) return fallback;
    const YAML::Node n = node_[key];
    if (!n.IsScalar()) fail(full(key), "expected text");
    return n.as<std::string>();
  }
  /// A name shown on one line (progress, reports, CSV): text without control characters (a
  /// newline would split the line); `fallback` when absent, checked alike.
  std::string name(const std::string& key, const std::string& fallback) {
    const std::string v = text(key, fallback);
    for (unsigned char c : v)
      if (c < 0x20 || c == 0x7f)
        fail(full(key), fmt::format("expected a name without control characters, got one with "
                                    "character {:#04x}",
                                    c));
    return v;
  }
  template <std::size_t N>
  std::array<double, N> numbers(const std::string& key) {
    return to_numbers<N>(require(key), full(key));
  }
  template <std::size_t N>
  std::array<double, N> numbers(const std::string& key, std::array<double, N> fallback) {
    return has(key) ? to_numbers<N>(node_[key], full(key)) : fallback;
  }
  int integer(const std::string& key) {
    const double v = number(key);
    if (v != std::floor(v) || std::abs(v) > 1e6)
      fail(full(key), fmt::format("expected a whole number in -1000000..1000000, got {}", v));
    return static_cast<int>(v);
  }
  template <std::size_t N>
  std::array<int, N> integers(const std::string& key) {
    const auto v = numbers<N>(key);
    std::array<int, N> out{};
    for (std::size_t i = 0; i < N; ++i) {
      if (v[i] != std::floor(v[i]) || std::abs(v[i]) > 1e6)
        fail(full(key), fmt::format("expected whole numbers in -1000000..1000000, got {}", v[i]));
      out[i] = static_cast<int>(v[i]);
    }
    return out;
  }
  std::vector<std::string> texts(const std::string& key) {
    const YAML::Node n = require(key);
    if (!n.IsSequence()) fail(full(key), "expected a list of names");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < n.size(); ++i) {
      if (!n[i].IsScalar()) fail(fmt::format("{}[{}]", full(key), i), "expected a name");
      out.push_back(n[i].as<std::string>());
    }
    return out;
  }
  MapReader child(const std::string& key) { return MapReader(require(key), source_, full(key)); }
  bool has_child(const std::string& key) { return has(key); }

  /// Throws on any key not read so far.
  void finish() const {
    for (const auto& kv : node_) {
      const auto key = kv.first.as<std::string>();
      if (!seen_.count(key)) fail(full(key), "unknown key");
    }
  }

  std::string full(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  [[noreturn]] void fail(const std::string& what, const std::string& why) const {
    throw InputError(fmt::format("{}: {}: {}", source_, what, why));
  }
  const std::string& source() const { return source_; }

  double to_number(const YAML::Node& n, const std::string& what) const {
    if (!n.IsScalar()) fail(what, "expected a number");
    const std::string s = n.as<std::string>();
    double v = 0.0;
    std::size_t used = 0;
    try {
      v = std::stod(s, &used);
    } catch (const std::exception&) {
      fail(what, fmt::format("expected a number, got '{}'", s));
    }
    if (used != s.size()) fail(what, fmt::format("expected a number, got '{}'", s));
    if (!std::isfinite(v)) fail(what, fmt::format("expected a finite number, got '{}'", s));
    return v;
  }
  template <std::size_t N>
  std::array<double, N> to_numbers(const YAML::Node& n, const std::string& what) const {
    if (!n.IsSequence() || n.size() != N)
      fail(what, fmt::format("expected a list of {} numbers", N));
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = to_number(n[i], fmt::format("{}[{}]", what, i));
    return out;
  }

 private:
  YAML::Node node_;
  std::string source_;
  std::string path_;
  std::set<std::string> seen_;
};

}  // namespace mg::field
