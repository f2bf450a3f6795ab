#include "core/io.hpp"

#include <atomic>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <climits>

#include <fmt/format.h>
#include <pthread.h>

#include "core/error.hpp"

namespace mg {

namespace {

std::string file_kind(std::filesystem::file_type t) {
  using std::filesystem::file_type;
  switch (t) {
    case file_type::directory:
      return "a directory";
    case file_type::symlink:
      return "a symbolic link";
    case file_type::fifo:
      return "a FIFO";
    case file_type::socket:
      return "a socket";
    case file_type::block:
    case file_type::character:
      return "a device";
    default:
      return "not a regular file";
  }
}

std::string errno_text(int err) {
  if (err == ENAMETOOLONG) return "file name too long";
  if (err == ENOENT || err == ENOTDIR) return "no such file";
  return std::strerror(err);
}

}  // namespace

std::string shown_path(const std::filesystem::path& path) {
  const std::string& s = path.native();
  constexpr std::size_t kMax = 160;
  if (s.size() <= kMax) return s;
  return fmt::format("{}...{} ({} characters)", s.substr(0, 60), s.substr(s.size() - 60), s.size());
}

namespace {

/// /dev/null is the one non-regular input allowed: the empty file, read at once.
bool is_dev_null(const struct stat& st) {
  struct stat null {};
  return S_ISCHR(st.st_mode) && ::stat("/dev/null", &null) == 0 && st.st_rdev == null.st_rdev;
}

std::uintmax_t check_input_stat(const std::filesystem::path& path, const struct stat& st,
                                std::uintmax_t max_bytes) {
  if (S_ISDIR(st.st_mode))
    throw IoError(fmt::format("{}: is a directory, expected a file", shown_path(path)));
  if (is_dev_null(st)) return 0;
  if (!S_ISREG(st.st_mode)) {
    const auto type = std::filesystem::status(path).type();
    throw IoError(fmt::format("{}: is {}; input files must be regular files", shown_path(path),
                              file_kind(type)));
  }
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > max_bytes)
    throw IoError(fmt::format("{}: is {} bytes; input files are limited to {} MiB",
                              shown_path(path), size, max_bytes >> 20));
  return size;
}

}  // namespace

std::uintmax_t check_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw IoError(fmt::format("{}: {}", shown_path(path), errno_text(errno)));
  return check_input_stat(path, st, max_bytes);
}

std::string read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  // O_NONBLOCK, then fstat: a FIFO swapped in after a check can neither block the open nor be read.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw IoError(fmt::format("{}: {}", shown_path(path), errno_text(errno)));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw IoError(fmt::format("{}: {}", shown_path(path), errno_text(errno)));
  const std::uintmax_t size = check_input_stat(path, st, max_bytes);
  std::string text;
  text.reserve(static_cast<std::size_t>(size));
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      throw IoError(fmt::format("{}: read failed: {}", shown_path(path), std::strerror(errno)));
    if (n == 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    if (text.size() > max_bytes)  // it grew while we read
      throw IoError(
          fmt::format("{}: grew past {} MiB while being read", shown_path(path), max_bytes >> 20));
  }
  return text;
}

void check_output_file(const std::filesystem::path& path) {
  if (path.empty()) throw IoError("output: expected a file name, got ''");
  if (path.native().size() >= PATH_MAX)
    throw IoError(fmt::format("{}: file name too long", shown_path(path)));
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (!S_ISREG(st.st_mode))
      throw IoError(fmt::format("{}: is {}; refusing to replace it (write to a regular file)",
                                shown_path(path),
                                file_kind(std::filesystem::symlink_status(path).type())));
  } else if (errno != ENOENT) {
    throw IoError(fmt::format("{}: {}", shown_path(path), errno_text(errno)));
  }
  std::filesystem::path folder = path.parent_path();
  if (folder.empty()) folder = ".";
  struct stat dst {};
  if (::stat(folder.c_str(), &dst) != 0)
    throw IoError(
        fmt::format("{}: output folder '{}' does not exist", shown_path(path), shown_path(folder)));
  if (!S_ISDIR(dst.st_mode))
    throw IoError(fmt::format("{}: '{}' is not a folder", shown_path(path), shown_path(folder)));
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw IoError(fmt::format("{}: output folder '{}' is not writable ({})", shown_path(path),
                              shown_path(folder), std::strerror(errno)));
}

void ensure_output_dir(const std::filesystem::path& path) {
  if (path.empty()) throw IoError("output folder: expected a name, got ''");
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode))
      throw IoError(fmt::format("{}: is {}, expected a folder", shown_path(path),
                                file_kind(std::filesystem::symlink_status(path).type())));
  } else {
    if (errno != ENOENT) throw IoError(fmt::format("{}: {}", shown_path(path), errno_text(errno)));
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (ec)
      throw IoError(fmt::format("{}: cannot make the folder: {}", shown_path(path), ec.message()));
  }
  if (::access(path.c_str(), W_OK | X_OK) != 0)
    throw IoError(
        fmt::format("{}: folder is not writable ({})", shown_path(path), std::strerror(errno)));
}

namespace {

// Temporary files of writes in progress, removed by the handler of SIGINT / SIGTERM / SIGHUP so a
// killed write leaves nothing behind (unlink is async-signal-safe; the slots are plain buffers).
constexpr int kTempSlots = 32;
constexpr std::size_t kTempPathMax = 4096;
struct TempSlot {
  std::atomic<bool> used{false};
  char path[kTempPathMax] = {};
};
TempSlot g_temp_slots[kTempSlots];

void remove_temp_files() noexcept {
  for (auto& slot : g_temp_slots)
    if (slot.used.load()) ::unlink(slot.path);
}

// Deferred termination (defer_termination_signals): the first signal is recorded in g_pending;
// one delivered to another thread is forwarded to g_input_thread so its blocking read returns.
std::atomic<bool> g_defer{false};
std::atomic<int> g_pending{0};
std::atomic<bool> g_forwarded{false};
pthread_t g_input_thread{};

/// Removes the temp files and raises `sig` with its default action. In the signal's handler the
/// signal is blocked: it ends the process when the handler returns.
void raise_default(int sig) noexcept {
  remove_temp_files();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

extern "C" void on_termination_signal(int sig) {
  if (g_defer.load()) {
    if (g_forwarded.exchange(false) && g_pending.load() == sig) return;  // our own forward
    int none = 0;
    if (g_pending.compare_exchange_strong(none, sig)) {
      if (!pthread_equal(pthread_self(), g_input_thread)) {
        g_forwarded.store(true);
        pthread_kill(g_input_thread, sig);
      }
      return;
    }
  }
  raise_default(sig);
}

/// Installs on_termination_signal for SIGINT / SIGTERM / SIGHUP; `always`: also over a handler
/// somebody else installed (else only where the default action is in place). No SA_RESTART:
/// a blocking read is interrupted.
void install_termination_handlers(bool always) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    ::sigaction(sig, nullptr, &old);
    if (!always && old.sa_handler != SIG_DFL) continue;  // somebody else handles it
    struct sigaction sa {};
    sa.sa_handler = on_termination_signal;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

/// Registers `tmp` for removal on a signal; returns the slot (-1: none free or too long).
int register_temp(const std::filesystem::path& tmp) {
  static std::once_flag handlers;
  std::call_once(handlers, [] { install_termination_handlers(false); });
  const std::string& text = tmp.native();
  if (text.size() + 1 > kTempPathMax) return -1;
  for (int i = 0; i < kTempSlots; ++i) {
    bool expected = false;
    if (g_temp_slots[i].used.compare_exchange_strong(expected, true)) {
      std::memcpy(g_temp_slots[i].path, text.c_str(), text.size() + 1);
      return i;
    }
  }
  return -1;
}

void unregister_temp(int slot) {
  if (slot >= 0) g_temp_slots[slot].used.store(false);
}

}  // namespace

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  // Never replace what is not a regular file (a FIFO, a device, a link): refuse it.
  std::error_code st_ec;
  const auto st = std::filesystem::symlink_status(path, st_ec);
  if (!st_ec && std::filesystem::exists(st) && st.type() != std::filesystem::file_type::regular)
    throw IoError(fmt::format("{}: is {}; refusing to replace it (write to a regular file)",
                              shown_path(path), file_kind(st.type())));
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path tmp =
      path.string() + fmt::format(".{}.{}.tmp", static_cast<long>(::getpid()), counter++);
  const int slot = register_temp(tmp);
  struct Unregister {
    int slot;
    ~Unregister() { unregister_temp(slot); }
  } unregister{slot};
  {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw IoError(fmt::format("{}: cannot open for writing", path.string()));
    const bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size() &&
                    std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
    std::fclose(f);
    if (!ok) {
      std::remove(tmp.c_str());
      throw IoError(fmt::format("{}: write failed", path.string()));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw IoError(fmt::format("{}: cannot replace file: {}", path.string(), ec.message()));
  }
}

void defer_termination_signals() {
  g_input_thread = pthread_self();
  g_defer.store(true);
  install_termination_handlers(true);
}

int termination_signal() noexcept { return g_pending.load(); }

void terminate_by_signal(int signal) {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, signal);
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  raise_default(signal);
  std::_Exit(128 + signal);  // a signal whose default is to go on (not one of ours)
}

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("MINIGOLF_DATA_DIR"); env && *env) return env;
  // A data folder is one with the shipped fields in it.
  auto usable = [](const std::filesystem::path& p) {
    std::error_code ec;
    return std::filesystem::is_directory(p / "fields", ec);
  };
  static const std::filesystem::path found = [&] {
    // Installed or copied (`cmake --install`: bin/minigolf + share/minigolf/data): the data
    // beside the executable wins over the source tree recorded at build time.
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec)
      for (const auto& c :
           {exe.parent_path() / ".." / "share" / "minigolf" / "data", exe.parent_path() / "data"})
        if (usable(c)) return c.lexically_normal();
    // Then the source tree recorded at build time, then the installed package's data (a program
    // built against `find_package(minigolf)`, the source tree gone).
    const std::filesystem::path source(MINIGOLF_DATA_DIR), installed(MINIGOLF_INSTALLED_DATA_DIR);
    if (!usable(source) && usable(installed)) return installed;
    return source;
  }();
  return found;
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string format_exact(double value) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
  if (ec != std::errc()) return fmt::format("{}", value);
  return std::string(buf, end);
}

}  // namespace mg
