#include "common/udp_over_tcp/stream_link.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>
#include <vector>

namespace mostar::udp_over_tcp {
namespace {

using Datagram = std::vector<uint8_t>;

Datagram Bytes(size_t size, uint32_t seed) {
  Datagram d(size);
  for (size_t i = 0; i < size; ++i) d[i] = static_cast<uint8_t>(seed * 31 + i);
  return d;
}

struct Pair {
  Pair() { EXPECT_EQ(socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0); }
  int fds[2] = {-1, -1};
};

// Writes from `from` and reads at `to` until neither makes progress.
std::vector<Datagram> Pump(StreamLink& from, StreamLink& to) {
  std::vector<Datagram> got;
  std::string error;
  for (int i = 0; i < 1000; ++i) {
    EXPECT_TRUE(from.OnWritable(&error)) << error;
    EXPECT_TRUE(
        to.OnReadable([&](const uint8_t* d, size_t s) { got.emplace_back(d, d + s); }, &error))
        << error;
    if (!from.wants_write()) break;
  }
  EXPECT_TRUE(
      to.OnReadable([&](const uint8_t* d, size_t s) { got.emplace_back(d, d + s); }, &error));
  return got;
}

TEST(StreamLinkTest, CarriesDatagramsBothWays) {
  Pair p;
  StreamLink a(p.fds[0], {}), b(p.fds[1], {});
  std::vector<Datagram> a_to_b, b_to_a;
  for (uint32_t i = 0; i < 20; ++i) a_to_b.push_back(Bytes(1 + i * 70, i));
  for (uint32_t i = 0; i < 5; ++i) b_to_a.push_back(Bytes(1452, 100 + i));
  for (const auto& d : a_to_b) a.Send(d.data(), d.size());
  for (const auto& d : b_to_a) b.Send(d.data(), d.size());
  EXPECT_EQ(Pump(a, b), a_to_b);
  EXPECT_EQ(Pump(b, a), b_to_a);
  EXPECT_TRUE(a.preamble_received());
  EXPECT_TRUE(b.preamble_received());
  EXPECT_EQ(a.counters().datagrams_sent, 20u);
  EXPECT_EQ(b.counters().datagrams_received, 20u);
  EXPECT_EQ(a.counters().datagrams_dropped, 0u);
}

TEST(StreamLinkTest, APeerThatStopsReadingCostsDropsNotMemory) {
  Pair p;
  StreamLinkOptions options;
  options.queue_bytes = 8 * 1024;
  StreamLink a(p.fds[0], options), b(p.fds[1], {});
  std::string error;
  // b does not read: the socket pair's buffer fills, then a's queue, then datagrams drop.
  uint32_t sent = 0;
  for (; sent < 2000; ++sent) {
    const Datagram d = Bytes(1000, sent);
    a.Send(d.data(), d.size());
    ASSERT_TRUE(a.OnWritable(&error)) << error;
  }
  EXPECT_GT(a.counters().datagrams_dropped, 0u);
  EXPECT_LT(a.counters().datagrams_dropped, sent);
  // b reads everything now: the datagrams that got through are in order and end with the
  // newest, and every datagram is either delivered or counted as dropped.
  std::vector<Datagram> got = Pump(a, b);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back(), Bytes(1000, sent - 1));
  EXPECT_EQ(got.size() + a.counters().datagrams_dropped, sent);
}

TEST(StreamLinkTest, GarbageFromThePeerEndsTheLinkWithAReason) {
  Pair p;
  StreamLink a(p.fds[0], {});
  const std::string garbage = "SSH-2.0-OpenSSH_9.2\r\n";
  ASSERT_EQ(write(p.fds[1], garbage.data(), garbage.size()), static_cast<ssize_t>(garbage.size()));
  std::string error;
  EXPECT_FALSE(
      a.OnReadable([](const uint8_t*, size_t) { FAIL() << "no datagram expected"; }, &error));
  EXPECT_THAT(error, testing::HasSubstr("bad preamble"));
  close(p.fds[1]);
}

TEST(StreamLinkTest, AnOversizeFrameEndsTheLink) {
  Pair p;
  StreamLinkOptions options;
  options.max_datagram_bytes = 1500;
  StreamLink a(p.fds[0], options), b(p.fds[1], {});
  const Datagram big = Bytes(2000, 1);
  b.Send(big.data(), big.size());
  std::string error;
  ASSERT_TRUE(b.OnWritable(&error));
  EXPECT_FALSE(a.OnReadable([](const uint8_t*, size_t) {}, &error));
  EXPECT_THAT(error, testing::HasSubstr("exceeds the limit of 1500"));
}

TEST(StreamLinkTest, EndOfStreamIsReported) {
  Pair p;
  StreamLink a(p.fds[0], {});
  close(p.fds[1]);
  std::string error;
  EXPECT_FALSE(a.OnReadable([](const uint8_t*, size_t) {}, &error));
  EXPECT_THAT(error, testing::HasSubstr("closed by the peer"));
}

}  // namespace
}  // namespace mostar::udp_over_tcp
