// Socket set-up of the UDP-over-TCP tunnel: endpoint parsing and the TCP options that keep
// the connection's latency bounded and notice a dead path within seconds.
#pragma once

#include <netinet/in.h>
#include <sys/socket.h>

#include <cstddef>
#include <string>

namespace mostar::udp_over_tcp {

// "HOST:PORT" (HOST a name or an IPv4 address; "[IPV6]:PORT" for IPv6). False with *error when
// the text is not of that form or PORT is not 1..65535 (0..65535 with allow_port_0: "any").
bool SplitHostPort(const std::string& text, std::string* host, int* port, std::string* error,
                   bool allow_port_0 = false);

// A numeric IPv4 "A.B.C.D:PORT" as a socket address (the local ends: listen addresses, port 0
// for any when allow_port_0, the WireGuard port). False with *error otherwise.
bool ParseIpv4Endpoint(const std::string& text, sockaddr_in* address, std::string* error,
                       bool allow_port_0 = false);

struct TcpTuning {
  // Unacknowledged (or unsendable) data older than this ends the connection (TCP_USER_TIMEOUT).
  int user_timeout_ms = 4000;
  // An idle connection is probed after keepalive_idle_s, every keepalive_interval_s.
  int keepalive_idle_s = 1;
  int keepalive_interval_s = 1;
  int keepalive_count = 3;
  // Bytes written but not yet sent above which poll() stops reporting the socket writable
  // (TCP_NOTSENT_LOWAT); the StreamLink's max_unsent_bytes.
  size_t notsent_lowat_bytes = 16 * 1024;
  // Congestion control (TCP_CONGESTION), "" for the system's default. BBR keeps a lossy long
  // path near its rate where loss-based CUBIC backs off at every random loss.
  std::string congestion = "bbr";
};

// Applies TCP_NODELAY, TCP_NOTSENT_LOWAT, TCP_USER_TIMEOUT, keepalive and the congestion
// control to a TCP socket. Returns false with *error when a required option fails; an
// unavailable congestion control is not fatal: *warning says so and the default stays.
bool ConfigureTcpSocket(int fd, const TcpTuning& tuning, std::string* warning, std::string* error);

// The local port a socket is bound to (0 when unknown).
int BoundPort(int fd);

// "A.B.C.D:PORT" (or "[V6]:PORT") of a socket address, for logs.
std::string FormatAddress(const sockaddr* address, socklen_t length);

}  // namespace mostar::udp_over_tcp
