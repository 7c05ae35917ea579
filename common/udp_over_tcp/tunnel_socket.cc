#include "common/udp_over_tcp/tunnel_socket.h"

#include <arpa/inet.h>
#include <netinet/tcp.h>

#include <cerrno>
#include <cstring>

namespace mostar::udp_over_tcp {
namespace {

bool SetInt(int fd, int level, int name, int value, const char* what, std::string* error) {
  if (setsockopt(fd, level, name, &value, sizeof(value)) == 0) return true;
  *error = std::string(what) + ": " + std::strerror(errno);
  return false;
}

}  // namespace

bool SplitHostPort(const std::string& text, std::string* host, int* port, std::string* error,
                   bool allow_port_0) {
  std::string port_text;
  if (!text.empty() && text.front() == '[') {
    const size_t close = text.find(']');
    if (close == std::string::npos || close + 1 >= text.size() || text[close + 1] != ':') {
      *error = "'" + text + "' is not [IPV6]:PORT";
      return false;
    }
    *host = text.substr(1, close - 1);
    port_text = text.substr(close + 2);
  } else {
    const size_t colon = text.rfind(':');
    if (colon == std::string::npos || colon == 0 || text.find(':') != colon) {
      *error = "'" + text + "' is not HOST:PORT";
      return false;
    }
    *host = text.substr(0, colon);
    port_text = text.substr(colon + 1);
  }
  if (host->empty() || port_text.empty() || port_text.size() > 5 ||
      port_text.find_first_not_of("0123456789") != std::string::npos) {
    *error = "'" + text + "' is not HOST:PORT";
    return false;
  }
  *port = std::stoi(port_text);
  if (*port < (allow_port_0 ? 0 : 1) || *port > 65535) {
    *error = "port " + port_text + " is not " + (allow_port_0 ? "0" : "1") + "..65535";
    return false;
  }
  return true;
}

bool ParseIpv4Endpoint(const std::string& text, sockaddr_in* address, std::string* error,
                       bool allow_port_0) {
  std::string host;
  int port = 0;
  if (!SplitHostPort(text, &host, &port, error, allow_port_0)) return false;
  *address = sockaddr_in{};
  address->sin_family = AF_INET;
  address->sin_port = htons(static_cast<uint16_t>(port));
  if (inet_pton(AF_INET, host.c_str(), &address->sin_addr) != 1) {
    *error = "'" + host + "' is not an IPv4 address";
    return false;
  }
  return true;
}

bool ConfigureTcpSocket(int fd, const TcpTuning& tuning, std::string* warning, std::string* error) {
  if (!SetInt(fd, IPPROTO_TCP, TCP_NODELAY, 1, "TCP_NODELAY", error) ||
      !SetInt(fd, IPPROTO_TCP, TCP_NOTSENT_LOWAT, static_cast<int>(tuning.notsent_lowat_bytes),
              "TCP_NOTSENT_LOWAT", error) ||
      !SetInt(fd, IPPROTO_TCP, TCP_USER_TIMEOUT, tuning.user_timeout_ms, "TCP_USER_TIMEOUT",
              error) ||
      !SetInt(fd, SOL_SOCKET, SO_KEEPALIVE, 1, "SO_KEEPALIVE", error) ||
      !SetInt(fd, IPPROTO_TCP, TCP_KEEPIDLE, tuning.keepalive_idle_s, "TCP_KEEPIDLE", error) ||
      !SetInt(fd, IPPROTO_TCP, TCP_KEEPINTVL, tuning.keepalive_interval_s, "TCP_KEEPINTVL",
              error) ||
      !SetInt(fd, IPPROTO_TCP, TCP_KEEPCNT, tuning.keepalive_count, "TCP_KEEPCNT", error)) {
    return false;
  }
  warning->clear();
  if (!tuning.congestion.empty() &&
      setsockopt(fd, IPPROTO_TCP, TCP_CONGESTION, tuning.congestion.data(),
                 static_cast<socklen_t>(tuning.congestion.size())) != 0) {
    *warning = "congestion control '" + tuning.congestion + "' unavailable (" +
               std::strerror(errno) + "), using the system's default";
  }
  return true;
}

int BoundPort(int fd) {
  sockaddr_in bound{};
  socklen_t length = sizeof(bound);
  if (getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &length) != 0) return 0;
  return ntohs(bound.sin_port);
}

std::string FormatAddress(const sockaddr* address, socklen_t length) {
  char host[INET6_ADDRSTRLEN] = "?";
  if (address->sa_family == AF_INET && length >= sizeof(sockaddr_in)) {
    const auto* in = reinterpret_cast<const sockaddr_in*>(address);
    inet_ntop(AF_INET, &in->sin_addr, host, sizeof(host));
    return std::string(host) + ":" + std::to_string(ntohs(in->sin_port));
  }
  if (address->sa_family == AF_INET6 && length >= sizeof(sockaddr_in6)) {
    const auto* in6 = reinterpret_cast<const sockaddr_in6*>(address);
    inet_ntop(AF_INET6, &in6->sin6_addr, host, sizeof(host));
    return "[" + std::string(host) + "]:" + std::to_string(ntohs(in6->sin6_port));
  }
  return "?";
}

}  // namespace mostar::udp_over_tcp
