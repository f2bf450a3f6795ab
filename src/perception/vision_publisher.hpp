#pragma once
/// A simulated stereo-vision system inside a running program: observes the true ball and hole,
/// adds noise, latency and dropouts, and sends `minigolf-vision/1` datagrams over UDP. The
/// console's `--vision-sim` uses it so normal mode runs end to end on loopback.
///
/// Clocked from outside (`update(now, ...)`, seconds on the caller's clock, the simulated time),
/// so a lockstep run publishes the same messages whatever the wall clock does. Seeded.
#include <array>
#include <cstdint>
#include <deque>
#include <string>

#include "core/rng.hpp"
#include "perception/udp.hpp"

namespace mg::perception {

struct VisionPublisherConfig {
  double rate = 60.0;    ///< [Hz] captures per second
  double noise = 0.0;    ///< [m] Gaussian std added to every coordinate
  double latency = 0.0;  ///< [s] from capture to send
  double dropout = 0.0;  ///< probability a capture is not sent
  std::uint64_t seed = 1;
  void validate() const;  ///< throws InputError naming the field
};

class VisionPublisher {
 public:
  /// Sends to host:port. Throws IoError (socket) or InputError (config).
  VisionPublisher(const std::string& host, std::uint16_t port, const VisionPublisherConfig& config);

  /// Captures when a capture is due (at most one per call) and sends what is due by `now`.
  void update(double now, const std::array<double, 3>& ball, const std::array<double, 3>& hole);

  std::uint64_t sent() const { return sent_; }
  std::uint64_t dropped() const { return dropped_; }

 private:
  struct Pending {
    double due;
    std::string datagram;
  };
  UdpSender sender_;
  VisionPublisherConfig config_;
  Rng rng_;
  std::deque<Pending> pending_;
  double next_capture_ = 0.0;
  std::uint64_t seq_ = 0;
  std::uint64_t sent_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace mg::perception
