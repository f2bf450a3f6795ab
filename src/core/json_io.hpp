#pragma once
/// The one checked JSON reader: every JSON input (learner models, hitting models) comes through
/// here, so every malformed file gives the same one-line InputError naming the file.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace mg {

/// Parses `text` (from `source`, used in the message). Throws `InputError` "SOURCE: not valid
/// JSON (...)" on a syntax error and "SOURCE: number out of range (...)" on e.g. `1e999`.
nlohmann::json parse_json(const std::string& text, const std::string& source);

/// `read_text_file` + `parse_json` (IoError if unreadable, InputError if malformed).
nlohmann::json read_json_file(const std::filesystem::path& path);

}  // namespace mg
