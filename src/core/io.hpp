#pragma once
/// File helpers: whole-file reads with clear errors, and atomic writes (temp file + rename) so
/// an interrupted run never leaves a half-written file in place of a good one.
#include <filesystem>
#include <string>
#include <string_view>

namespace mg {

/// Reads a whole file; throws `IoError` naming the path if it cannot.
std::string read_text_file(const std::filesystem::path& path);

/// Writes `content` to `path` atomically: a sibling temp file, flushed, then renamed over.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// Directory holding the shipped data (fields, demonstrations, models): `$MINIGOLF_DATA_DIR`
/// if set, else `<exe>/../share/minigolf/data` or `<exe>/data` if it holds `fields/` (an
/// installed or copied build), else the source tree's `data/` recorded at build time.
std::filesystem::path data_dir();

/// `s` as one single-quoted POSIX shell word (for commands run through std::system).
std::string shell_quote(const std::string& s);

/// Formats a double so that parsing it back gives the same bits (shortest round-trip form).
std::string format_exact(double value);

}  // namespace mg
