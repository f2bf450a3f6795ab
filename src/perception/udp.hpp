#pragma once
/// Minimal RAII UDP sockets (POSIX, IPv4) for the vision feed.
///
/// The receiver is non-blocking: `receive` returns at once, never throws and never allocates, so
/// the control loop may poll it every tick. Construction is the only place that can fail; it
/// throws `mg::IoError` naming the address and port.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace mg::perception {

/// Owns one socket file descriptor (closed on destruction; movable, not copyable).
class UdpSocket {
 public:
  UdpSocket() = default;
  explicit UdpSocket(int fd) : fd_(fd) {}
  UdpSocket(UdpSocket&& other) noexcept : fd_(other.release()) {}
  UdpSocket& operator=(UdpSocket&& other) noexcept;
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;
  ~UdpSocket();
  int fd() const { return fd_; }
  int release() noexcept;

 private:
  int fd_ = -1;
};

/// A bound, non-blocking UDP socket.
class UdpReceiver {
 public:
  /// Binds to `bind_address` (dotted IPv4, e.g. "127.0.0.1" or "0.0.0.0") and `port` (0 = an
  /// ephemeral port; see `port()`). Throws `IoError` naming address and port on failure.
  UdpReceiver(const std::string& bind_address, std::uint16_t port);

  /// Reads one pending datagram into `buffer`. Returns its size in bytes, or nothing when no
  /// datagram is pending (or on a socket error). A datagram longer than the buffer is cut to the
  /// buffer's size (so give one byte more than the longest valid datagram to detect that).
  /// Real-time safe: never blocks, throws or allocates.
  std::optional<std::size_t> receive(std::span<char> buffer) noexcept;

  /// The bound port (the kernel's choice when constructed with port 0).
  std::uint16_t port() const { return port_; }

 private:
  UdpSocket socket_;
  std::uint16_t port_ = 0;
};

/// A UDP socket that sends datagrams to one destination.
class UdpSender {
 public:
  /// `address`: dotted IPv4 or a host name (resolved once, here). Throws `IoError`.
  UdpSender(const std::string& address, std::uint16_t port);

  /// Sends one datagram; returns false if the kernel refused it (e.g. too long, no route).
  /// Never throws.
  bool send(std::string_view datagram) noexcept;

 private:
  UdpSocket socket_;
};

/// Splits "HOST:PORT" (port 1-65535). Throws `InputError` naming `what`.
std::pair<std::string, std::uint16_t> parse_host_port(const std::string& what,
                                                      const std::string& text);

}  // namespace mg::perception
