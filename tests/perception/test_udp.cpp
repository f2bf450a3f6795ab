#include <gtest/gtest.h>

#include <array>
#include <string>

#include "core/error.hpp"
#include "perception/udp.hpp"

namespace mg::perception {
namespace {

TEST(Udp, LoopbackRoundTripOnEphemeralPort) {
  UdpReceiver rx("127.0.0.1", 0);
  ASSERT_NE(rx.port(), 0);
  std::array<char, 64> buf{};
  EXPECT_FALSE(rx.receive(buf)) << "nothing sent yet: receive must return at once, empty";
  UdpSender tx("127.0.0.1", rx.port());
  ASSERT_TRUE(tx.send("hello"));
  ASSERT_TRUE(tx.send("second"));
  const auto a = rx.receive(buf);
  ASSERT_TRUE(a);
  EXPECT_EQ(std::string(buf.data(), *a), "hello");
  const auto b = rx.receive(buf);
  ASSERT_TRUE(b);
  EXPECT_EQ(std::string(buf.data(), *b), "second");
  EXPECT_FALSE(rx.receive(buf));
}

TEST(Udp, LongDatagramIsCutToTheBuffer) {
  UdpReceiver rx("127.0.0.1", 0);
  UdpSender tx("localhost", rx.port());
  ASSERT_TRUE(tx.send(std::string(100, 'x')));
  std::array<char, 10> buf{};
  const auto n = rx.receive(buf);
  ASSERT_TRUE(n);
  EXPECT_EQ(*n, buf.size());
  EXPECT_FALSE(rx.receive(buf)) << "the rest of a cut datagram must not arrive as another one";
}

TEST(Udp, EmptyDatagramIsReceivedAsSizeZero) {
  UdpReceiver rx("127.0.0.1", 0);
  UdpSender tx("127.0.0.1", rx.port());
  ASSERT_TRUE(tx.send(""));
  std::array<char, 8> buf{};
  const auto n = rx.receive(buf);
  ASSERT_TRUE(n);
  EXPECT_EQ(*n, 0u);
}

TEST(Udp, ConstructionErrorsNameAddressAndPort) {
  UdpReceiver first("127.0.0.1", 0);
  try {
    UdpReceiver second("127.0.0.1", first.port());
    FAIL() << "binding a port twice must throw";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(first.port())),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(UdpReceiver("not an address..", 0), IoError);
  EXPECT_THROW(UdpSender("no-such-host.invalid", 47001), IoError);
}

TEST(Udp, SendingToNobodyDoesNotThrowOrFailForever) {
  std::uint16_t port = 0;
  {
    UdpReceiver rx("127.0.0.1", 0);
    port = rx.port();
  }  // closed: the port now refuses (ICMP on loopback)
  UdpSender tx("127.0.0.1", port);
  for (int i = 0; i < 5; ++i) tx.send("x");  // must return, whatever the result
  SUCCEED();
}

TEST(Udp, ParseHostPort) {
  EXPECT_EQ(parse_host_port("--to", "127.0.0.1:47001"),
            std::make_pair(std::string("127.0.0.1"), std::uint16_t{47001}));
  EXPECT_EQ(parse_host_port("--to", "localhost:1").first, "localhost");
  for (const char* bad : {"", ":1", "host", "host:", "host:0", "host:65536", "host:12x", "host:-1"})
    EXPECT_THROW(parse_host_port("--to", bad), InputError) << bad;
}

}  // namespace
}  // namespace mg::perception
