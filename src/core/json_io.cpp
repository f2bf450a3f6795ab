#include "core/json_io.hpp"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"

namespace mg {
namespace {

/// The keys of the objects being parsed, innermost last: a parser callback's state. Keys of one
/// object are few (a model has about ten), so a linear search is the fast choice.
class KeyCheck {
 public:
  /// Records a parser event; false once a key repeats in its object.
  bool event(nlohmann::json::parse_event_t e, const nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if (e == Event::object_start) {
      open_.emplace_back();
    } else if (e == Event::object_end) {
      if (!open_.empty()) open_.pop_back();
    } else if (e == Event::key && !open_.empty() && parsed.is_string()) {
      auto& keys = open_.back();
      const auto& k = parsed.get_ref<const std::string&>();
      if (std::find(keys.begin(), keys.end(), k) != keys.end()) {
        if (!duplicate_) duplicate_ = k;
        return false;
      }
      keys.push_back(k);
    }
    return true;
  }
  const std::optional<std::string>& duplicate() const { return duplicate_; }

 private:
  std::vector<std::vector<std::string>> open_;
  std::optional<std::string> duplicate_;
};

/// A key for a one-line message: control characters escaped, long keys shortened.
std::string shown_key(const std::string& key) {
  std::string out;
  for (unsigned char c : key.substr(0, 80))
    out += c < 0x20 || c == 0x7f ? '?' : static_cast<char>(c);
  if (key.size() > 80) out += fmt::format("... ({} characters)", key.size());
  return out;
}

}  // namespace

nlohmann::json parse_json(std::string_view text, const std::string& source) {
  if (const auto nul = text.find('\0'); nul != std::string_view::npos)
    throw InputError(fmt::format("{}: not valid JSON (a NUL byte at offset {})", source, nul));
  KeyCheck keys;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(
        text, [&keys](int, nlohmann::json::parse_event_t e, nlohmann::json& parsed) {
          return keys.event(e, parsed);
        });
  } catch (const nlohmann::json::out_of_range& e) {
    throw InputError(fmt::format("{}: number out of range ({})", source, e.what()));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON ({})", source, e.what()));
  }
  if (keys.duplicate())
    throw InputError(fmt::format("{}: duplicate key '{}' (a key may appear once per object)",
                                 source, shown_key(*keys.duplicate())));
  return j;
}

std::optional<nlohmann::json> try_parse_json(std::string_view text) {
  if (text.find('\0') != std::string_view::npos) return std::nullopt;
  KeyCheck keys;
  nlohmann::json j = nlohmann::json::parse(
      text,
      [&keys](int, nlohmann::json::parse_event_t e, nlohmann::json& parsed) {
        return keys.event(e, parsed);
      },
      false);
  if (j.is_discarded() || keys.duplicate()) return std::nullopt;
  return j;
}

nlohmann::json read_json_file(const std::filesystem::path& path) {
  return parse_json(read_text_file(path), path.string());
}

}  // namespace mg
