#pragma once
/// The stereo-vision feed's message (normal mode, thesis 4.2.1): ball and hole positions.
///
/// Transport: UDP, one datagram per message, UTF-8 JSON, at most 512 bytes:
///
///     {"format": "minigolf-vision/1", "seq": 42, "stamp": 12.345,
///      "ball": [x, y, z], "hole": [x, y, z]}
///
/// `seq` increases by at least one per message (a receiver drops repeats and reordered
/// datagrams); `stamp` is the capture time in seconds on the sender's monotonic clock; positions
/// are metres in the world frame of the field. Parsing is a pure function: it never throws,
/// never trusts the sender, and says why a message was rejected.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace mg::perception {

/// Largest accepted `seq` (2^53: exact in every JSON implementation's doubles). A larger one is
/// out of range: one datagram with seq 2^64-1 would otherwise make every later one "reordered".
inline constexpr std::uint64_t kMaxVisionSeq = 9007199254740992ULL;

struct VisionMessage {
  std::uint64_t seq = 0;                ///< 0..kMaxVisionSeq
  double stamp = 0.0;                   ///< [s] sender clock
  std::array<double, 3> ball{0, 0, 0};  ///< [m] world frame
  std::array<double, 3> hole{0, 0, 0};  ///< [m] world frame
};

enum class VisionError { kNone, kTooLong, kMalformed, kWrongFormat, kNotFinite, kOutOfRange };

struct VisionParse {
  VisionError error = VisionError::kNone;
  VisionMessage message;
};

/// Where positions may lie: the lane's bounds with a margin, and a height band. [m]
struct VisionLimits {
  std::array<double, 4> bounds{-0.5, 3.0, -1.0, 1.0};  ///< [x_min, x_max, y_min, y_max]
  double z_min = -0.5;
  double z_max = 1.0;
};

inline constexpr std::size_t kMaxVisionMessageBytes = 512;
inline constexpr std::string_view kVisionFormat = "minigolf-vision/1";

/// Parses and checks one datagram. Never throws.
VisionParse parse_vision_message(std::string_view datagram, const VisionLimits& limits);

/// Formats a message (what `minigolf vision-sim` sends).
std::string format_vision_message(const VisionMessage& message);

std::string_view to_string(VisionError error);

}  // namespace mg::perception
