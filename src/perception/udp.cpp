#include "perception/udp.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <utility>

#include "core/error.hpp"

namespace mg::perception {
namespace {

[[noreturn]] void fail(std::string_view what, const std::string& address, std::uint16_t port,
                       int err) {
  throw IoError(fmt::format("UDP {} {}:{}: {}", what, address, port, std::strerror(err)));
}

sockaddr_in resolve(const std::string& address, std::uint16_t port, std::string_view what) {
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(port);
  if (::inet_pton(AF_INET, address.c_str(), &sa.sin_addr) == 1) return sa;
  // Not a dotted address: resolve a host name (IPv4 only).
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(address.c_str(), nullptr, &hints, &found);
  if (rc != 0 || found == nullptr)
    throw IoError(fmt::format("UDP {} {}:{}: cannot resolve the address ({})", what, address, port,
                              rc != 0 ? ::gai_strerror(rc) : "no IPv4 address"));
  sa.sin_addr = reinterpret_cast<const sockaddr_in*>(found->ai_addr)->sin_addr;
  ::freeaddrinfo(found);
  return sa;
}

}  // namespace

UdpSocket& UdpSocket::operator=(UdpSocket&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.release();
  }
  return *this;
}

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) ::close(fd_);
}

int UdpSocket::release() noexcept { return std::exchange(fd_, -1); }

UdpReceiver::UdpReceiver(const std::string& bind_address, std::uint16_t port) {
  const sockaddr_in sa = resolve(bind_address, port, "bind to");
  socket_ = UdpSocket(::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (socket_.fd() < 0) fail("socket for", bind_address, port, errno);
  if (::bind(socket_.fd(), reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0)
    fail("bind to", bind_address, port, errno);
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  if (::getsockname(socket_.fd(), reinterpret_cast<sockaddr*>(&bound), &len) != 0)
    fail("getsockname of", bind_address, port, errno);
  port_ = ntohs(bound.sin_port);
}

std::optional<std::size_t> UdpReceiver::receive(std::span<char> buffer) noexcept {
  for (;;) {
    const ssize_t n = ::recv(socket_.fd(), buffer.data(), buffer.size(), MSG_DONTWAIT);
    if (n >= 0) return static_cast<std::size_t>(n);
    // EINTR: retry; EAGAIN: nothing pending; anything else (e.g. ECONNREFUSED left by an ICMP
    // error) also means "nothing to read now".
    if (errno != EINTR) return std::nullopt;
  }
}

UdpSender::UdpSender(const std::string& address, std::uint16_t port) {
  const sockaddr_in sa = resolve(address, port, "send to");
  socket_ = UdpSocket(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  if (socket_.fd() < 0) fail("socket for", address, port, errno);
  // A connected UDP socket: `send` needs no address, and the kernel filters replies.
  if (::connect(socket_.fd(), reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0)
    fail("connect to", address, port, errno);
}

bool UdpSender::send(std::string_view datagram) noexcept {
  for (int attempt = 0; attempt < 4; ++attempt) {
    const ssize_t n = ::send(socket_.fd(), datagram.data(), datagram.size(), 0);
    if (n >= 0) return static_cast<std::size_t>(n) == datagram.size();
    // ECONNREFUSED: an earlier datagram found no listener (loopback ICMP); a vision feed keeps
    // sending regardless, so retry this one once the error is consumed.
    if (errno == EINTR || errno == ECONNREFUSED) continue;
    return false;
  }
  return false;
}

std::pair<std::string, std::uint16_t> parse_host_port(const std::string& what,
                                                      const std::string& text) {
  const auto colon = text.rfind(':');
  const auto bad = [&] {
    return InputError(
        fmt::format("{}: expected HOST:PORT with a port in 1-65535, got '{}'", what, text));
  };
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) throw bad();
  unsigned port = 0;
  const char* first = text.data() + colon + 1;
  const char* last = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(first, last, port);
  if (ec != std::errc{} || ptr != last || port < 1 || port > 65535) throw bad();
  return {text.substr(0, colon), static_cast<std::uint16_t>(port)};
}

}  // namespace mg::perception
