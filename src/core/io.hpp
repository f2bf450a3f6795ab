#pragma once
/// File helpers: whole-file reads with clear errors, and atomic writes (temp file + rename) so
/// an interrupted run never leaves a half-written file in place of a good one.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace mg {

/// Input files are at most this large (a bound, so /dev/zero or a runaway file cannot exhaust
/// memory; the largest shipped file is under 1 MiB).
inline constexpr std::uintmax_t kMaxInputFileBytes = 256ull << 20;

/// Checks that `path` names a regular file (following links) of at most `max_bytes` and returns
/// its size. Refuses with one `IoError` line a missing file, a name too long, a directory, and
/// FIFOs, devices and sockets: they could block forever or never end.
std::uintmax_t check_input_file(const std::filesystem::path& path,
                                std::uintmax_t max_bytes = kMaxInputFileBytes);

/// Checks that `path` can take a new file through `write_file_atomic` before expensive work
/// starts: its folder exists and is writable, and `path` is absent or a regular file (never a
/// link, FIFO, device or folder). Throws `IoError` naming the problem.
void check_output_file(const std::filesystem::path& path);

/// Checks that `path` is, or can be made as, a writable folder (never through a link); makes it.
void ensure_output_dir(const std::filesystem::path& path);

/// `path` for a one-line message: long names are shortened in the middle.
std::string shown_path(const std::filesystem::path& path);

/// Reads a whole regular file (see `check_input_file`); throws `IoError` naming the path if it
/// cannot.
std::string read_text_file(const std::filesystem::path& path,
                           std::uintmax_t max_bytes = kMaxInputFileBytes);

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
/// installed or copied build), else the source tree's `data/` recorded at build time, or, if that
/// is gone, `<install prefix>/share/minigolf/data` of the configured prefix (a program using the
/// installed package; after `cmake --install --prefix` elsewhere, set `$MINIGOLF_DATA_DIR`).
std::filesystem::path data_dir();

/// `s` as one single-quoted POSIX shell word (for commands run through std::system).
std::string shell_quote(const std::string& s);

/// Formats a double so that parsing it back gives the same bits (shortest round-trip form).
std::string format_exact(double value);

}  // namespace mg
