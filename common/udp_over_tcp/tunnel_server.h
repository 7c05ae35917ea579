// The hub side of the UDP-over-TCP tunnel (mostar_wg_tcp server): accepts TCP clients and
// gives each one its own UDP socket towards the hub's WireGuard port, so WireGuard sees every
// client as a UDP endpoint of its own (a reconnecting client is a new endpoint, which
// WireGuard follows at its next authenticated packet, as it does when a peer roams). Memory
// per client is bounded (StreamLinkOptions); at most max_clients at a time, more are refused.
// A client that sends no preamble within preamble_timeout_ms is closed. Single-threaded use.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/udp_over_tcp/stream_link.h"
#include "common/udp_over_tcp/tunnel_socket.h"

namespace mostar::udp_over_tcp {

struct TunnelServerOptions {
  std::string listen = "0.0.0.0:51821";       // TCP address (IPv4) clients dial
  std::string wireguard = "127.0.0.1:51820";  // the hub's WireGuard UDP port (IPv4)
  int max_clients = 64;
  int preamble_timeout_ms = 5000;
  StreamLinkOptions link;
  TcpTuning tcp;
};

struct TunnelServerCounters {
  uint64_t tcp_in = 0;         // datagrams from clients, handed to WireGuard
  uint64_t tcp_out = 0;        // datagrams from WireGuard, queued to clients
  uint64_t dropped_queue = 0;  // pushed out of send queues (all clients)
  uint64_t dropped_udp = 0;    // towards WireGuard, refused by the local socket
  uint64_t accepted = 0;       // connections accepted
  uint64_t refused = 0;        // over max_clients
  uint64_t closed = 0;         // connections ended (by either side, errors included)
  size_t clients = 0;          // connected now
};

class TunnelServer {
 public:
  explicit TunnelServer(TunnelServerOptions options);
  ~TunnelServer();
  TunnelServer(const TunnelServer&) = delete;
  TunnelServer& operator=(const TunnelServer&) = delete;

  // Checks the options and listens. False with *error (a message naming the option).
  bool Open(std::string* error);
  // The TCP port actually bound (useful with port 0).
  int port() const { return port_; }

  // One round of the event loop: waits at most timeout_ms for any socket, then serves them.
  void Poll(int timeout_ms);

  TunnelServerCounters counters() const;
  // Events worth a log line since the last call (client connected, ended and why).
  std::vector<std::string> TakeEvents();

 private:
  struct Client;
  void Accept();
  void Close(size_t index, const std::string& why);

  TunnelServerOptions options_;
  sockaddr_in wireguard_{};
  int listen_fd_ = -1;
  int port_ = 0;
  std::vector<std::unique_ptr<Client>> clients_;
  uint64_t dropped_queue_closed_ = 0;
  TunnelServerCounters counters_;
  std::vector<std::string> events_;
};

}  // namespace mostar::udp_over_tcp
