#include "control/recorder.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/io.hpp"

namespace mg::control {

void Recorder::start(const std::filesystem::path& path) {
  if (active_) throw InputError(fmt::format("record: already recording to '{}'", path_.string()));
  if (path.empty() || !path.has_filename())
    throw InputError(fmt::format("record: expected a file name, got '{}'", path.string()));
  try {
    check_output_file(path);  // refused now, not at `record off` after the whole run
  } catch (const IoError& e) {
    throw IoError(fmt::format("record: {}", e.what()));
  }
  rows_.clear();
  rows_.reserve(kCapacity);
  dropped_ = 0;
  path_ = path;
  active_ = true;
}

void Recorder::record(const RecordSample& sample) noexcept {
  if (!active_) return;
  if (rows_.size() < rows_.capacity())
    rows_.push_back(sample);
  else
    ++dropped_;
}

std::size_t Recorder::stop() {
  if (!active_) return 0;
  write_file_atomic(path_, format_recording(rows_));
  active_ = false;
  const std::size_t n = rows_.size();
  rows_.clear();
  rows_.shrink_to_fit();
  return n;
}

std::string format_recording(const std::vector<RecordSample>& rows) {
  std::string out = "t,state";
  for (const char* g : {"q", "qd", "tau"})
    for (int j = 1; j <= 7; ++j) out += fmt::format(",{}{}", g, j);
  out +=
      ",face_x,face_y,face_z,ball_x,ball_y,ball_z,seen_ball_x,seen_ball_y,seen_ball_z,"
      "seen_hole_x,seen_hole_y,fresh,angle,speed\n";
  auto append = [&out](double v) { fmt::format_to(std::back_inserter(out), ",{}", v); };
  for (const RecordSample& s : rows) {
    fmt::format_to(std::back_inserter(out), "{},{}", s.t, s.state);
    for (double v : s.q) append(v);
    for (double v : s.qd) append(v);
    for (double v : s.tau) append(v);
    for (double v : s.face) append(v);
    for (double v : s.ball) append(v);
    for (double v : s.seen_ball) append(v);
    for (double v : s.seen_hole) append(v);
    out += s.fresh ? ",1" : ",0";
    append(s.angle);
    append(s.speed);
    out += '\n';
  }
  return out;
}

}  // namespace mg::control
