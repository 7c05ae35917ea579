// The tunnel end to end on loopback, in one process: a "WireGuard" UDP socket on each side,
// the client and the server between them over TCP.
#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/udp_over_tcp/tunnel_client.h"
#include "common/udp_over_tcp/tunnel_server.h"

namespace mostar::udp_over_tcp {
namespace {

// A UDP socket on 127.0.0.1 (port 0: any).
struct UdpSocket {
  UdpSocket() {
    fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
    socklen_t n = sizeof(a);
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
    port = ntohs(a.sin_port);
  }
  ~UdpSocket() { close(fd); }
  void SendTo(int to_port, const std::string& text) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<uint16_t>(to_port));
    sendto(fd, text.data(), text.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof(a));
  }
  // A received datagram, or "" when none; *from_port gets the sender's port.
  std::string Receive(int* from_port = nullptr) {
    char buffer[70000];
    sockaddr_in a{};
    socklen_t n = sizeof(a);
    const ssize_t got =
        recvfrom(fd, buffer, sizeof(buffer), MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&a), &n);
    if (got <= 0) return "";
    if (from_port != nullptr) *from_port = ntohs(a.sin_port);
    return std::string(buffer, static_cast<size_t>(got));
  }
  int fd;
  int port;
};

std::string Endpoint(int port) { return "127.0.0.1:" + std::to_string(port); }

class TunnelTest : public testing::Test {
 protected:
  void StartServer(int port) {
    TunnelServerOptions options;
    options.listen = Endpoint(port);
    options.wireguard = Endpoint(hub_wg.port);
    options.max_clients = max_clients;
    options.preamble_timeout_ms = 500;
    server = std::make_unique<TunnelServer>(options);
    std::string error;
    ASSERT_TRUE(server->Open(&error)) << error;
  }
  void StartClient() {
    TunnelClientOptions options;
    options.listen = Endpoint(0);
    options.hub = Endpoint(server->port());
    options.connect_timeout_ms = 1000;
    options.initial_backoff_ms = 50;
    options.max_backoff_ms = 200;
    client = std::make_unique<TunnelClient>(options);
    std::string error;
    ASSERT_TRUE(client->Open(&error)) << error;
  }
  // Runs both event loops until `done` holds; false after 10 s (a failure, not a speed limit).
  bool RunUntil(const std::function<bool()>& done) {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < give_up) {
      if (server) server->Poll(5);
      if (client) client->Poll(5);
      if (done()) return true;
    }
    return false;
  }
  // Sends `text` from the host's WireGuard until the hub's WireGuard receives it (the first
  // datagrams are dropped while the tunnel dials); returns the port the hub saw it from.
  int HostToHub(const std::string& text) {
    int from = 0;
    EXPECT_TRUE(RunUntil([&] {
      host_wg.SendTo(client->port(), text);
      std::string got;
      for (int i = 0; i < 10; ++i) {
        client->Poll(1);
        server->Poll(1);
        got = hub_wg.Receive(&from);
        if (!got.empty()) break;
      }
      return got == text;
    })) << text;
    return from;
  }

  int max_clients = 8;
  UdpSocket host_wg, hub_wg;
  std::unique_ptr<TunnelServer> server;
  std::unique_ptr<TunnelClient> client;
};

TEST_F(TunnelTest, CarriesDatagramsBothWays) {
  StartServer(0);
  StartClient();
  const int endpoint = HostToHub("handshake initiation");
  ASSERT_NE(endpoint, 0);
  EXPECT_TRUE(client->connected());
  // The hub's WireGuard answers to the endpoint it saw; the host's WireGuard gets it.
  hub_wg.SendTo(endpoint, "handshake response");
  std::string got;
  EXPECT_TRUE(RunUntil([&] { return (got = host_wg.Receive()) == "handshake response"; }));
  const std::string big(1452, 'x');
  // A burst within the queue's capacity arrives whole and in order.
  for (int i = 0; i < 30; ++i) host_wg.SendTo(client->port(), big + std::to_string(i));
  std::vector<std::string> received;
  EXPECT_TRUE(RunUntil([&] {
    for (std::string d = hub_wg.Receive(); !d.empty(); d = hub_wg.Receive()) {
      received.push_back(d);
    }
    return received.size() >= 30;
  }));
  ASSERT_EQ(received.size(), 30u);
  for (int i = 0; i < 30; ++i) EXPECT_EQ(received[i], big + std::to_string(i));
  EXPECT_EQ(client->counters().dropped_queue, 0u);
  EXPECT_EQ(server->counters().clients, 1u);
  EXPECT_EQ(client->counters().connects, 1u);
}

TEST_F(TunnelTest, DialsAgainWhenTheHubRestartsAndIsANewEndpoint) {
  StartServer(0);
  StartClient();
  const int port = server->port();
  const int first = HostToHub("before");
  server.reset();  // the hub's tunnel goes away: the client notices the closed connection
  EXPECT_TRUE(RunUntil([&] { return !client->connected(); }));
  StartServer(port);
  const int second = HostToHub("after");
  EXPECT_NE(first, second);  // a new UDP socket towards WireGuard: WireGuard roams to it
  EXPECT_GE(client->counters().connects, 2u);
  EXPECT_GE(client->counters().failures, 1u);
}

// While the hub is unreachable the newest datagrams are held; the new connection carries them
// first, so the hub's WireGuard hears this host at its new tunnel endpoint at once.
TEST_F(TunnelTest, TheNewestDatagramsOfAnOutageGoFirstOnTheNewConnection) {
  StartServer(0);
  const int port = server->port();
  StartClient();
  server.reset();  // before the client's first dial: nothing listens, every dial is refused
  for (int i = 0; i < 20; ++i) host_wg.SendTo(client->port(), "d" + std::to_string(i));
  EXPECT_TRUE(RunUntil([&] { return client->counters().udp_in == 20; }));
  EXPECT_FALSE(client->connected());
  EXPECT_EQ(client->counters().dropped_no_link, 12u);
  StartServer(port);
  std::vector<std::string> received;
  EXPECT_TRUE(RunUntil([&] {
    for (std::string d = hub_wg.Receive(); !d.empty(); d = hub_wg.Receive()) {
      received.push_back(d);
    }
    return received.size() >= 8;
  }));
  ASSERT_EQ(received.size(), 8u);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(received[i], "d" + std::to_string(12 + i));
  EXPECT_EQ(client->counters().held_sent, 8u);
  // Once sent they are gone: a later reconnection does not repeat them.
  EXPECT_EQ(HostToHub("after"), HostToHub("after again"));
  EXPECT_EQ(client->counters().held_sent, 8u);
}

// A path that answers nothing (here: the hub's accept queue full, so its kernel drops every
// SYN, as a dead link would): a new dial starts every interval beside the pending ones, so when
// the path answers again a fresh SYN gets through without waiting for TCP's 1 s retransmission.
TEST_F(TunnelTest, ASilentPathGetsANewDialEveryIntervalUntilItAnswers) {
  StartServer(0);  // not polled yet: it accepts nothing
  std::vector<int> fillers;
  for (int i = 0; i < 80; ++i) {  // more than the server's listen backlog (64)
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<uint16_t>(server->port()));
    connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a));
    fillers.push_back(fd);
  }
  StartClient();
  const auto silent_until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (std::chrono::steady_clock::now() < silent_until) client->Poll(5);
  EXPECT_FALSE(client->connected());
  EXPECT_GE(client->counters().dials, 3u);  // not one dial waiting for its SYN's retransmission
  EXPECT_EQ(client->counters().connects, 0u);
  for (const int fd : fillers) close(fd);  // the server may now accept (and drop) them
  EXPECT_TRUE(RunUntil([&] { return client->connected(); }));
  EXPECT_EQ(client->counters().connects, 1u);
}

// A hub name that does not resolve (yet): the lookup is retried with the dial backoff, not back
// to back, and the tunnel connects once the name resolves.
TEST_F(TunnelTest, AFailedLookupIsRetriedWithBackoffUntilTheNameResolves) {
  StartServer(0);
  // Shared with the lookup's thread, which may outlive the client by a moment.
  const auto name_known = std::make_shared<std::atomic<bool>>(false);
  const int hub_port = server->port();
  TunnelClientOptions options;
  options.listen = Endpoint(0);
  options.hub = "hub.example:" + std::to_string(hub_port);
  options.initial_backoff_ms = 50;
  options.max_backoff_ms = 200;
  options.lookup = [name_known](const std::string& host, int port, sockaddr_storage* address,
                                socklen_t* length) -> std::string {
    if (!*name_known) return "cannot resolve " + host + ": Name or service not known";
    return LookUpWithGetaddrinfo("127.0.0.1", port, address, length);
  };
  client = std::make_unique<TunnelClient>(options);
  std::string error;
  ASSERT_TRUE(client->Open(&error)) << error;

  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(1)) client->Poll(5);
  const TunnelClientCounters c = client->counters();
  // Backoff 50, 100, 200, 200... ms: about 7 lookups in 1 s; back to back it would be ~50+.
  EXPECT_GE(c.lookups, 3u);
  EXPECT_LE(c.lookups, 12u);
  EXPECT_EQ(c.dials, 0u);
  EXPECT_THAT(client->TakeEvents(),
              testing::Contains(testing::HasSubstr("cannot resolve hub.example")));

  *name_known = true;
  EXPECT_TRUE(RunUntil([&] { return client->connected(); }));
  EXPECT_EQ(client->counters().connects, 1u);
  const uint64_t after_connect = client->counters().lookups;
  for (int i = 0; i < 50; ++i) RunUntil([] { return true; });
  EXPECT_EQ(client->counters().lookups, after_connect);  // none while connected
}

TEST_F(TunnelTest, ServerClosesAClientThatSendsGarbage) {
  StartServer(0);
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<uint16_t>(server->port()));
  ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
  const std::string garbage = "GET / HTTP/1.1\r\n\r\n";
  ASSERT_EQ(write(fd, garbage.data(), garbage.size()), static_cast<ssize_t>(garbage.size()));
  EXPECT_TRUE(RunUntil([&] { return server->counters().closed == 1; }));
  EXPECT_EQ(server->counters().clients, 0u);
  std::vector<std::string> events = server->TakeEvents();
  EXPECT_THAT(events, testing::Contains(testing::HasSubstr("bad preamble")));
  close(fd);
}

TEST_F(TunnelTest, ServerClosesAClientWithoutPreambleAndRefusesOverTheLimit) {
  max_clients = 1;
  StartServer(0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<uint16_t>(server->port()));
  const int silent = socket(AF_INET, SOCK_STREAM, 0);
  const int second = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_EQ(connect(silent, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
  EXPECT_TRUE(RunUntil([&] { return server->counters().clients == 1; }));
  ASSERT_EQ(connect(second, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
  EXPECT_TRUE(RunUntil([&] { return server->counters().refused == 1; }));
  EXPECT_TRUE(RunUntil([&] { return server->counters().closed == 1; }));  // preamble timeout
  EXPECT_EQ(server->counters().clients, 0u);
  close(silent);
  close(second);
}

TEST(TunnelOptionsTest, BadOptionsAreRefusedWithTheOptionNamed) {
  std::string error;
  TunnelClientOptions client;
  client.hub = "no-port";
  EXPECT_FALSE(TunnelClient(client).Open(&error));
  EXPECT_THAT(error, testing::HasSubstr("--hub"));
  client.hub = "hub.example.org:443";
  client.listen = "localhost:51821";
  EXPECT_FALSE(TunnelClient(client).Open(&error));
  EXPECT_THAT(error, testing::HasSubstr("--listen"));
  TunnelServerOptions server;
  server.wireguard = "127.0.0.1:99999";
  EXPECT_FALSE(TunnelServer(server).Open(&error));
  EXPECT_THAT(error, testing::HasSubstr("--wireguard"));
}

TEST(SplitHostPortTest, AcceptsNamesAddressesAndBracketedIpv6) {
  std::string host, error;
  int port = 0;
  EXPECT_TRUE(SplitHostPort("hub.example.org:443", &host, &port, &error));
  EXPECT_EQ(host, "hub.example.org");
  EXPECT_EQ(port, 443);
  EXPECT_TRUE(SplitHostPort("[2001:db8::1]:51821", &host, &port, &error));
  EXPECT_EQ(host, "2001:db8::1");
  EXPECT_FALSE(SplitHostPort("2001:db8::1:443", &host, &port, &error));
  EXPECT_FALSE(SplitHostPort("hub:0", &host, &port, &error));
  EXPECT_FALSE(SplitHostPort("hub:", &host, &port, &error));
  EXPECT_FALSE(SplitHostPort(":443", &host, &port, &error));
}

}  // namespace
}  // namespace mostar::udp_over_tcp
