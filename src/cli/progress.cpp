#include "cli/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>

namespace mg::cli {

Progress::Progress(std::string what, int total)
    : what_(std::move(what)),
      total_(std::max(total, 1)),
      tty_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()) {}

void Progress::update(int done, const std::string& note) {
  const double f = std::clamp(static_cast<double>(done) / total_, 0.0, 1.0);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double eta = done > 0 ? elapsed * (total_ - done) / done : 0.0;
  if (tty_) {
    const int width = 30, filled = static_cast<int>(f * width);
    fmt::print(stderr, "\r{} [{}{}] {}/{} {:.0f} s, ETA {:.0f} s {}\033[K", what_,
               std::string(filled, '#'), std::string(width - filled, ' '), done, total_, elapsed,
               eta, note);
    open_ = true;
  } else {
    const int decile = static_cast<int>(f * 10.0);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    fmt::print(stderr, "{}: {}/{} ({:.0f} s) {}\n", what_, done, total_, elapsed, note);
  }
  std::fflush(stderr);
}

void Progress::finish() {
  if (tty_) fmt::print(stderr, "\n");
  open_ = false;
}

Progress::~Progress() {
  if (open_) fmt::print(stderr, "\n");
}

}  // namespace mg::cli
