#include "common/udp_over_tcp/tunnel_server.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace mostar::udp_over_tcp {
namespace {

constexpr int kMaxUdpReadsPerPoll = 64;  // per client, then the others get their turn
constexpr int kMaxAcceptsPerPoll = 16;

}  // namespace

struct TunnelServer::Client {
  Client(int tcp_fd, int udp, std::string name, const StreamLinkOptions& options)
      : link(tcp_fd, options), udp_fd(udp), peer(std::move(name)) {}
  ~Client() { close(udp_fd); }
  StreamLink link;
  int udp_fd;  // connected to WireGuard
  std::string peer;
  std::chrono::steady_clock::time_point accepted = std::chrono::steady_clock::now();
};

TunnelServer::TunnelServer(TunnelServerOptions options) : options_(std::move(options)) {}

TunnelServer::~TunnelServer() {
  clients_.clear();
  if (listen_fd_ >= 0) close(listen_fd_);
}

bool TunnelServer::Open(std::string* error) {
  sockaddr_in listen_address{};
  if (!ParseIpv4Endpoint(options_.listen, &listen_address, error, true)) {
    *error = "--listen: " + *error;
    return false;
  }
  if (!ParseIpv4Endpoint(options_.wireguard, &wireguard_, error)) {
    *error = "--wireguard: " + *error;
    return false;
  }
  if (options_.max_clients < 1 || options_.preamble_timeout_ms <= 0) {
    *error = "--max-clients and the preamble timeout must be positive";
    return false;
  }
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  const int one = 1;
  if (listen_fd_ < 0 || setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one)) != 0 ||
      bind(listen_fd_, reinterpret_cast<const sockaddr*>(&listen_address),
           sizeof(listen_address)) != 0 ||
      listen(listen_fd_, 64) != 0) {
    *error = "cannot listen on TCP " + options_.listen + ": " + std::strerror(errno);
    return false;
  }
  std::string warning;
  // Accepted sockets inherit the congestion control from here, for their first packets too.
  ConfigureTcpSocket(listen_fd_, options_.tcp, &warning, error);
  if (!warning.empty()) events_.push_back(warning);
  port_ = BoundPort(listen_fd_);
  return true;
}

TunnelServerCounters TunnelServer::counters() const {
  TunnelServerCounters c = counters_;
  c.dropped_queue = dropped_queue_closed_;
  for (const auto& client : clients_) c.dropped_queue += client->link.counters().datagrams_dropped;
  c.clients = clients_.size();
  return c;
}

std::vector<std::string> TunnelServer::TakeEvents() { return std::exchange(events_, {}); }

void TunnelServer::Accept() {
  for (int i = 0; i < kMaxAcceptsPerPoll; ++i) {
    sockaddr_storage from{};
    socklen_t from_length = sizeof(from);
    const int fd = accept4(listen_fd_, reinterpret_cast<sockaddr*>(&from), &from_length,
                           SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;
    const std::string peer = FormatAddress(reinterpret_cast<sockaddr*>(&from), from_length);
    if (clients_.size() >= static_cast<size_t>(options_.max_clients)) {
      ++counters_.refused;
      events_.push_back("refused " + peer + ": already " + std::to_string(clients_.size()) +
                        " clients");
      close(fd);
      continue;
    }
    std::string warning, error;
    int udp = -1;
    if (ConfigureTcpSocket(fd, options_.tcp, &warning, &error)) {
      udp = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
      if (udp < 0 ||
          connect(udp, reinterpret_cast<const sockaddr*>(&wireguard_), sizeof(wireguard_)) != 0) {
        error = std::string("UDP socket towards WireGuard: ") + std::strerror(errno);
      }
    }
    if (!error.empty()) {
      events_.push_back("closed " + peer + ": " + error);
      if (udp >= 0) close(udp);
      close(fd);
      continue;
    }
    ++counters_.accepted;
    clients_.push_back(std::make_unique<Client>(fd, udp, peer, options_.link));
    events_.push_back("client " + peer + " connected (" + std::to_string(clients_.size()) +
                      " clients)");
  }
}

void TunnelServer::Close(size_t index, const std::string& why) {
  ++counters_.closed;
  dropped_queue_closed_ += clients_[index]->link.counters().datagrams_dropped;
  events_.push_back("client " + clients_[index]->peer + " closed: " + why + " (" +
                    std::to_string(clients_.size() - 1) + " clients)");
  clients_.erase(clients_.begin() + static_cast<std::ptrdiff_t>(index));
}

void TunnelServer::Poll(int timeout_ms) {
  std::vector<pollfd> fds;
  fds.reserve(1 + 2 * clients_.size());
  fds.push_back({listen_fd_, POLLIN, 0});
  for (const auto& c : clients_) {
    fds.push_back(
        {c->link.fd(), static_cast<short>(POLLIN | (c->link.wants_write() ? POLLOUT : 0)), 0});
    fds.push_back({c->udp_fd, POLLIN, 0});
  }
  if (poll(fds.data(), fds.size(), timeout_ms) < 0 && errno != EINTR) return;
  const auto now = std::chrono::steady_clock::now();
  static thread_local uint8_t buffer[kMaxDatagramBytes];

  // Clients polled above are clients_[0, polled); Accept() appends after them.
  const size_t polled = clients_.size();
  std::vector<std::string> closing(polled);
  for (size_t i = 0; i < polled; ++i) {
    Client& c = *clients_[i];
    const short tcp_events = fds[1 + 2 * i].revents;
    const short udp_events = fds[2 + 2 * i].revents;
    std::string error;
    bool ok = true;
    if (tcp_events & (POLLIN | POLLERR | POLLHUP)) {
      ok = c.link.OnReadable(
          [&](const uint8_t* d, size_t s) {
            if (send(c.udp_fd, d, s, MSG_DONTWAIT) == static_cast<ssize_t>(s)) {
              ++counters_.tcp_in;
            } else {
              ++counters_.dropped_udp;
            }
          },
          &error);
    }
    if (ok && !c.link.preamble_received() &&
        now - c.accepted > std::chrono::milliseconds(options_.preamble_timeout_ms)) {
      ok = false;
      error = "no preamble within " + std::to_string(options_.preamble_timeout_ms) + " ms";
    }
    if (ok && (udp_events & POLLIN)) {
      for (int k = 0; k < kMaxUdpReadsPerPoll; ++k) {
        const ssize_t n = recv(c.udp_fd, buffer, sizeof(buffer), MSG_DONTWAIT);
        if (n < 0) break;  // EAGAIN, or ICMP "refused" while WireGuard is down
        if (!c.link.preamble_received()) continue;
        ++counters_.tcp_out;
        c.link.Send(buffer, static_cast<size_t>(n));
        if (!(ok = c.link.OnWritable(&error))) break;  // the queue holds only the excess
      }
    }
    if (ok && c.link.wants_write()) ok = c.link.OnWritable(&error);
    if (!ok) closing[i] = error.empty() ? "error" : error;
  }
  for (size_t i = polled; i-- > 0;) {
    if (!closing[i].empty()) Close(i, closing[i]);
  }
  if (fds[0].revents & POLLIN) Accept();
}

}  // namespace mostar::udp_over_tcp
