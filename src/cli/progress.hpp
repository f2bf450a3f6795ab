#pragma once
/// Progress of long commands on stderr: a redrawn bar on a terminal, otherwise a line every 10 %.
#include <chrono>
#include <string>

namespace mg::cli {

class Progress {
 public:
  Progress(std::string what, int total);
  /// Ends a bar left open (an error thrown mid-run): its message then starts on its own line.
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  /// `done` of `total` finished; `note` is shown after the bar (e.g. putts spent).
  void update(int done, const std::string& note = "");
  void finish();

 private:
  std::string what_;
  int total_;
  bool tty_;
  int last_decile_ = -1;
  bool open_ = false;  ///< a bar is drawn and its line not ended
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mg::cli
