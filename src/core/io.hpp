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

/// Deferred termination, for a process that must save its work when interrupted (the console's
/// recording on Ctrl-C). After this call the first SIGINT, SIGTERM or SIGHUP only records the
/// signal and interrupts blocking calls (a read waiting for input returns) in the calling thread,
/// to which a signal delivered to another thread is forwarded: call it from the thread that
/// reads input. The process then finishes its work and ends with `terminate_by_signal`. A second
/// signal ends the process at once, removing the temp files of writes in progress.
void defer_termination_signals();
/// The deferred signal (SIGINT, SIGTERM, SIGHUP), 0 if none came. Async-signal-safe.
int termination_signal() noexcept;
/// Ends the process by `signal` with its default action (the exit status a shell expects),
/// removing temp files of writes in progress.
[[noreturn]] void terminate_by_signal(int signal);

/// Directory holding the shipped data (fields, demonstrations, models): `$MINIGOLF_DATA_DIR`
/// if set, else `<exe>/../share/minigolf/data` or `<exe>/data` if it holds `fields/` (an
/// installed or copied build), else the source tree's `data/` recorded at build time.
std::filesystem::path data_dir();

/// `s` as one single-quoted POSIX shell word (for commands run through std::system).
std::string shell_quote(const std::string& s);

/// Formats a double so that parsing it back gives the same bits (shortest round-trip form).
std::string format_exact(double value);

}  // namespace mg
