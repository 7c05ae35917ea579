// TCP_USER_TIMEOUT on this process's sockets: set on TCP sockets only, and it does drop a
// connection whose peer stopped reading (the case that blocks Fast DDS' TCP sends).
#include "common/dds/tcp_user_timeout.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <thread>
#include <vector>

namespace mostar::dds {
namespace {

int UserTimeout(int fd) {
  int value = -1;
  socklen_t length = sizeof(value);
  EXPECT_EQ(::getsockopt(fd, IPPROTO_TCP, TCP_USER_TIMEOUT, &value, &length), 0);
  return value;
}

// A listener on 127.0.0.1, a client connected to it and the accepted end.
struct Connection {
  int listener = -1, client = -1, accepted = -1;
  Connection() {
    listener = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
    EXPECT_EQ(::listen(listener, 1), 0);
    socklen_t length = sizeof(address);
    EXPECT_EQ(::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length), 0);
    client = ::socket(AF_INET, SOCK_STREAM, 0);
    EXPECT_EQ(::connect(client, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
    accepted = ::accept(listener, nullptr, nullptr);
    EXPECT_GE(accepted, 0);
  }
  ~Connection() {
    for (int fd : {listener, client, accepted}) {
      if (fd >= 0) ::close(fd);
    }
  }
};

TEST(TcpUserTimeoutTest, SetsEveryTcpSocketOnceAndLeavesOthersAlone) {
  Connection connection;
  const int udp = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(udp, 0);
  EXPECT_EQ(UserTimeout(connection.client), 0);  // the kernel default: no user timeout

  EXPECT_GE(ApplyTcpUserTimeout(1234), 3);
  EXPECT_EQ(UserTimeout(connection.listener), 1234);
  EXPECT_EQ(UserTimeout(connection.client), 1234);
  EXPECT_EQ(UserTimeout(connection.accepted), 1234);
  EXPECT_EQ(ApplyTcpUserTimeout(1234), 0) << "sockets that already have the value are skipped";
  int value = 0;
  socklen_t length = sizeof(value);
  EXPECT_NE(::getsockopt(udp, IPPROTO_TCP, TCP_USER_TIMEOUT, &value, &length), 0)
      << "a UDP socket was not touched (and has no such option)";
  EXPECT_EQ(ApplyTcpUserTimeout(0), 0) << "zero means off";
  ::close(udp);
}

TEST(TcpUserTimeoutTest, GuardDropsAConnectionWhosePeerStoppedReading) {
  Connection connection;
  TcpUserTimeoutGuard guard(300, std::chrono::milliseconds(20));
  for (int i = 0; i < 100 && UserTimeout(connection.client) != 300; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(UserTimeout(connection.client), 300);
  EXPECT_GE(guard.sockets_set(), 3);

  // The accepted end never reads: fill both buffers, then wait for the kernel to give up.
  ASSERT_EQ(::fcntl(connection.client, F_SETFL, O_NONBLOCK), 0);
  std::vector<char> block(64 * 1024, 'x');
  int error = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    const ssize_t sent = ::send(connection.client, block.data(), block.size(), MSG_NOSIGNAL);
    if (sent >= 0) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      error = errno;
      break;
    }
    pollfd p{connection.client, POLLOUT, 0};
    ::poll(&p, 1, 100);
  }
  EXPECT_EQ(error, ETIMEDOUT) << "the stalled connection was not dropped";
}

}  // namespace
}  // namespace mostar::dds
