#pragma once
/// The network vision feed: receives `minigolf-vision/1` datagrams, keeps the latest good one,
/// and counts what it rejects.
///
/// Time is injected: every call takes `now`, seconds on the caller's monotonic clock (the
/// control loop's), so the feed never reads a clock and tests are deterministic. Freshness is
/// judged by *receive* time, not by the sender's `stamp` (the two clocks are not synchronised):
/// the feed is fresh while the last accepted message arrived less than `max_age` ago.
///
/// Rejections (each counted once, the first reason wins):
///   too_long      datagram longer than kMaxVisionMessageBytes
///   malformed     not JSON, wrong shape, wrong format tag, non-finite numbers
///   out_of_range  a position outside `limits` (the lane's bounds plus a margin)
///   reordered     seq not greater than the last accepted seq (repeats and late datagrams)
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>

#include "field/field.hpp"
#include "perception/udp.hpp"
#include "perception/vision_message.hpp"

namespace mg::perception {

struct VisionFeedConfig {
  VisionLimits limits;
  double max_age = 0.2;  ///< [s] fresh while the last accepted message is younger than this
  /// At most this many datagrams are read per `poll`, so a flooding sender cannot stall the
  /// control loop; the rest wait for the next poll.
  int max_datagrams_per_poll = 1024;
  /// [s] A `seq` below the last accepted one is taken (a restarted sender) once nothing was
  /// accepted for this long, so no sender can blind the feed for good (a repeat of the last `seq`
  /// is always rejected).
  double seq_reset_after = 1.0;
  /// Throws `InputError` naming the field.
  void validate() const;
};

/// Limits for a field: its bounds plus `margin` [m] horizontally; heights from the lowest
/// surface point minus the cup depth to the highest plus `margin`, all with `margin` slack.
VisionLimits vision_limits_for(const field::Field& field, double margin = 0.1);

struct VisionCounters {
  std::uint64_t accepted = 0;
  std::uint64_t malformed = 0;
  std::uint64_t out_of_range = 0;
  std::uint64_t reordered = 0;
  std::uint64_t too_long = 0;
  std::uint64_t rejected() const { return malformed + out_of_range + reordered + too_long; }
  bool operator==(const VisionCounters&) const = default;
};

/// Why `offer` accepted or rejected a datagram.
enum class FeedVerdict { kAccepted, kMalformed, kOutOfRange, kReordered, kTooLong };

class VisionFeed {
 public:
  /// Reads from `receiver` (owned). Validates `config` (throws `InputError`).
  VisionFeed(UdpReceiver receiver, const VisionFeedConfig& config = {});

  /// Drains pending datagrams (up to `max_datagrams_per_poll`), all stamped as received at
  /// `now` [s]. Returns the number accepted. Never blocks or throws; allocates only inside the
  /// JSON parser.
  int poll(double now) noexcept;

  /// Judges one datagram received at `now` [s] (what `poll` does per datagram; public so the
  /// rules can be tested without sockets). Never throws.
  FeedVerdict offer(std::string_view datagram, double now) noexcept;

  /// The last accepted message, if any (ball and hole [m], world frame).
  const std::optional<VisionMessage>& latest() const { return latest_; }
  /// [s] since the last accepted message arrived; infinity before the first.
  double age(double now) const;
  /// True while the last accepted message is younger than `max_age`.
  bool fresh(double now) const { return age(now) < config_.max_age; }

  const VisionCounters& counters() const { return counters_; }
  const VisionFeedConfig& config() const { return config_; }
  std::uint16_t port() const { return receiver_.port(); }

 private:
  UdpReceiver receiver_;
  VisionFeedConfig config_;
  VisionCounters counters_;
  std::optional<VisionMessage> latest_;
  double latest_received_ = -std::numeric_limits<double>::infinity();  ///< [s] caller's clock
  // One byte over the limit, so an over-long datagram is seen as such (the kernel cuts it).
  std::array<char, kMaxVisionMessageBytes + 1> buffer_{};
};

}  // namespace mg::perception
