#pragma once
/// The module's recorder (thesis 4.2.2: the robot update records). Samples go into a buffer
/// reserved when recording starts, so `record` (called from the robot update) never allocates;
/// `stop` writes the whole CSV atomically, so a recording is either complete on disk or absent.
///
/// CSV columns (all numeric): t [s], state (0 Idle, 1 Rest, 2 Hitting, 3 Braking), q1..q7 [rad],
/// qd1..qd7 [rad/s], tau1..tau7 [N m], face_x/y/z [m] (club face centre, FK of the measured
/// joints), ball_x/y/z [m] (simulated truth), seen_ball_x/y/z, seen_hole_x/y [m] (the module's
/// perception), fresh (0/1), angle [rad], speed [m/s] (the console's current request).
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace mg::control {

struct RecordSample {
  double t = 0.0;
  int state = 0;
  std::array<double, 7> q{}, qd{}, tau{};
  std::array<double, 3> face{}, ball{}, seen_ball{};
  std::array<double, 2> seen_hole{};
  bool fresh = false;
  double angle = 0.0, speed = 0.0;
};

class Recorder {
 public:
  /// Rows kept per recording (20 min at the 100 Hz robot rate); later samples are counted as
  /// dropped.
  static constexpr std::size_t kCapacity = 120'000;

  /// Starts a recording to `path` (its folder must exist: IoError otherwise). Reserves the buffer.
  void start(const std::filesystem::path& path);
  /// Appends a sample if recording. Real-time safe: no allocation, no throw.
  void record(const RecordSample& sample) noexcept;
  /// Writes the CSV atomically and stops; returns the rows written. IoError on failure (the
  /// samples are kept, so `stop` can be retried).
  std::size_t stop();

  /// Counts `n` samples lost before they reached the recorder (a full ring) as dropped.
  void count_dropped(std::size_t n) noexcept { dropped_ += active_ ? n : 0; }

  bool active() const { return active_; }
  const std::filesystem::path& path() const { return path_; }
  std::size_t rows() const { return rows_.size(); }
  std::size_t dropped() const { return dropped_; }

 private:
  bool active_ = false;
  std::filesystem::path path_;
  std::vector<RecordSample> rows_;
  std::size_t dropped_ = 0;
};

/// The CSV text of samples (header + one line per sample).
std::string format_recording(const std::vector<RecordSample>& rows);

}  // namespace mg::control
