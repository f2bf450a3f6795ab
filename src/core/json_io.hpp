#pragma once
/// The one checked JSON reader: every JSON input (learner models, hitting models, vision
/// datagrams) comes through here, so every malformed text is refused the same way.
///
/// Beyond nlohmann's syntax check it refuses what nlohmann accepts silently: a key repeated in one
/// object (nlohmann keeps the last value) and a NUL byte (its lexer takes it for the end of the
/// input, so `{...}\0garbage` parsed as `{...}`).
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace mg {

/// Parses `text` (from `source`, used in the message). Throws `InputError` "SOURCE: not valid
/// JSON (...)" on a syntax error or a NUL byte, "SOURCE: number out of range (...)" on e.g.
/// `1e999`, and "SOURCE: duplicate key 'K' ..." on a key given twice in one object.
nlohmann::json parse_json(std::string_view text, const std::string& source);

/// The same checks without exceptions (hot I/O paths such as vision datagrams): nullopt for
/// anything `parse_json` refuses.
std::optional<nlohmann::json> try_parse_json(std::string_view text);

/// `read_text_file` + `parse_json` (IoError if unreadable, InputError if malformed).
nlohmann::json read_json_file(const std::filesystem::path& path);

}  // namespace mg
