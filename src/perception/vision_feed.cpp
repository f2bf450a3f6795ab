#include "perception/vision_feed.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"

namespace mg::perception {

void VisionFeedConfig::validate() const {
  if (!(std::isfinite(max_age) && max_age > 0.0))
    throw InputError(
        fmt::format("vision feed max_age: expected a finite number > 0 s, got {}", max_age));
  if (!(std::isfinite(seq_reset_after) && seq_reset_after > max_age))
    throw InputError(fmt::format(
        "vision feed seq_reset_after: expected a finite number > max_age ({} s), got {}", max_age,
        seq_reset_after));
  if (max_datagrams_per_poll < 1)
    throw InputError(fmt::format("vision feed max_datagrams_per_poll: expected >= 1, got {}",
                                 max_datagrams_per_poll));
  const auto& b = limits.bounds;
  if (!(b[0] < b[1] && b[2] < b[3] && limits.z_min < limits.z_max))
    throw InputError(
        fmt::format("vision feed limits: expected x_min < x_max, y_min < y_max, "
                    "z_min < z_max, got [{}, {}, {}, {}], z [{}, {}]",
                    b[0], b[1], b[2], b[3], limits.z_min, limits.z_max));
}

VisionLimits vision_limits_for(const field::Field& field, double margin) {
  VisionLimits l;
  const auto& b = field.bounds;
  l.bounds = {b[0] - margin, b[1] + margin, b[2] - margin, b[3] + margin};
  // Scan the surface on its own grid (once, at start-up) for the height band.
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  const double step = std::max(field.cell_size, 1e-3);
  for (double x = b[0]; x <= b[1] + 0.5 * step; x += step)
    for (double y = b[2]; y <= b[3] + 0.5 * step; y += step) {
      const double z = field.height(std::min(x, b[1]), std::min(y, b[3]));
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  // A ball in the cup sits below the surface; a bouncing ball or the border tops above it.
  l.z_min = lo - field.hole.depth - margin;
  l.z_max = hi + field.borders.height + 2.0 * field.ball.radius + margin;
  return l;
}

VisionFeed::VisionFeed(UdpReceiver receiver, const VisionFeedConfig& config)
    : receiver_(std::move(receiver)), config_(config) {
  config_.validate();
}

int VisionFeed::poll(double now) noexcept {
  int accepted = 0;
  for (int i = 0; i < config_.max_datagrams_per_poll; ++i) {
    const auto n = receiver_.receive(buffer_);
    if (!n) break;
    accepted += offer(std::string_view(buffer_.data(), *n), now) == FeedVerdict::kAccepted;
  }
  return accepted;
}

FeedVerdict VisionFeed::offer(std::string_view datagram, double now) noexcept {
  const VisionParse p = parse_vision_message(datagram, config_.limits);
  switch (p.error) {
    case VisionError::kNone:
      break;
    case VisionError::kTooLong:
      ++counters_.too_long;
      return FeedVerdict::kTooLong;
    case VisionError::kOutOfRange:
      ++counters_.out_of_range;
      return FeedVerdict::kOutOfRange;
    case VisionError::kMalformed:
    case VisionError::kWrongFormat:
    case VisionError::kNotFinite:
      ++counters_.malformed;
      return FeedVerdict::kMalformed;
  }
  // A lower seq after a silence is a restarted sender; a repeat of the last seq never refreshes.
  const bool restart = now - latest_received_ >= config_.seq_reset_after;
  if (latest_ && (p.message.seq == latest_->seq || (p.message.seq < latest_->seq && !restart))) {
    ++counters_.reordered;
    return FeedVerdict::kReordered;
  }
  ++counters_.accepted;
  latest_ = p.message;
  latest_received_ = now;
  return FeedVerdict::kAccepted;
}

double VisionFeed::age(double now) const {
  if (!latest_) return std::numeric_limits<double>::infinity();
  return now - latest_received_;
}

}  // namespace mg::perception
