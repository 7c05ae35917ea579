// The host side of the UDP-over-TCP tunnel (mostar_wg_tcp client): a local UDP port that the
// host's WireGuard uses as the hub's endpoint, and one TCP connection to the hub that carries
// its datagrams. Datagrams from the stream go to the last local UDP sender. A dropped
// connection (end of stream, reset, TCP user timeout, keepalive, protocol error, no preamble
// within connect_timeout_ms) is dialled again as DialPlan says: on a silent path a new dial
// every dial_interval_ms beside those in flight, so the tunnel follows the path back within
// about that plus a round trip; after an answered failure a backoff of initial_backoff_ms
// doubling to max_backoff_ms. Of the datagrams that arrive meanwhile the newest
// held_datagrams are kept and sent first on the next connection, the rest dropped and counted
// (WireGuard and DDS repair what matters): WireGuard takes a peer's endpoint from any datagram
// that authenticates, and these were never delivered, so they pass its replay check and the
// hub's WireGuard answers this host at its new tunnel at once instead of after its next
// keepalive. The hub's name is looked up on a thread of its own, so no step of Poll() blocks:
// again every 30 s while not connected (the last address is dialled meanwhile); a failed lookup
// with no address known yet is retried after DialPlan's backoff, not back to back.
// Single-threaded use.
#pragma once

#include <netinet/in.h>

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/udp_over_tcp/dial_plan.h"
#include "common/udp_over_tcp/stream_link.h"
#include "common/udp_over_tcp/tunnel_socket.h"

namespace mostar::udp_over_tcp {

// Looks up HOST:PORT for a TCP connection: "" with *address and *length set, or an error
// message. Called on a thread of its own. Tests replace it; the default is getaddrinfo.
using NameLookup = std::function<std::string(const std::string& host, int port,
                                             sockaddr_storage* address, socklen_t* length)>;
std::string LookUpWithGetaddrinfo(const std::string& host, int port, sockaddr_storage* address,
                                  socklen_t* length);

struct TunnelClientOptions {
  std::string listen = "127.0.0.1:51821";  // local UDP address (IPv4) for WireGuard
  std::string hub;                         // HOST:PORT of the hub's TCP port
  // Each dial's connect, and then the peer's preamble, within this: long enough for a lost
  // SYN's first retransmission (1 s) on a long path.
  int connect_timeout_ms = 1500;
  // A new dial every this often while none has an answer (DialPlan), at most
  // connect_timeout_ms / dial_interval_ms + 1 in flight.
  int dial_interval_ms = 250;
  int initial_backoff_ms = 250;
  int max_backoff_ms = 1000;
  int held_datagrams = 8;  // kept while not connected, sent first on the next connection
  StreamLinkOptions link;
  TcpTuning tcp;
  NameLookup lookup = LookUpWithGetaddrinfo;
};

struct TunnelClientCounters {
  uint64_t udp_in = 0;             // datagrams from the local WireGuard
  uint64_t udp_out = 0;            // datagrams delivered to it
  uint64_t dropped_no_link = 0;    // from WireGuard while not connected, beyond those held
  uint64_t held_sent = 0;          // held while not connected, sent once connected
  uint64_t dropped_queue = 0;      // pushed out of the send queue (all connections)
  uint64_t dropped_no_sender = 0;  // from the hub before WireGuard sent anything
  uint64_t connects = 0;           // connections established
  uint64_t dials = 0;              // dials started
  uint64_t lookups = 0;            // name lookups of the hub started
  uint64_t failures = 0;           // dials that failed and connections that ended
};

class TunnelClient {
 public:
  explicit TunnelClient(TunnelClientOptions options);
  ~TunnelClient();
  TunnelClient(const TunnelClient&) = delete;
  TunnelClient& operator=(const TunnelClient&) = delete;

  // Checks the options and binds the UDP port. False with *error (a message naming the option).
  bool Open(std::string* error);

  // One round of the event loop: waits at most timeout_ms for any socket, then serves them.
  void Poll(int timeout_ms);

  // The local UDP port bound by Open() (useful with port 0).
  int port() const { return port_; }
  bool connected() const { return link_ != nullptr && link_->preamble_received(); }
  TunnelClientCounters counters() const;
  // Events worth a log line since the last call (connected, dial failed and why).
  std::vector<std::string> TakeEvents();

 private:
  using Clock = std::chrono::steady_clock;
  struct Resolve;

  struct Dial {
    int fd = -1;
    Clock::time_point deadline;
  };

  void StartResolve();
  void FinishResolve(Clock::time_point now);
  void StartDial(Clock::time_point now);
  void FinishDial(size_t index, Clock::time_point now);
  void CloseDials();
  // A dial or connection failed: counted, said once per outage.
  void Failed(const std::string& why);
  void Drop(const std::string& why, Clock::time_point now);
  void ReadUdp();
  void Deliver(const uint8_t* datagram, size_t size);
  void SendHeld(Clock::time_point now);

  TunnelClientOptions options_;
  std::string hub_host_;
  int hub_port_ = 0;
  int udp_fd_ = -1;
  int port_ = 0;
  sockaddr_in sender_{};
  bool have_sender_ = false;
  std::shared_ptr<Resolve> resolve_;  // a name lookup in flight
  sockaddr_storage address_{};        // the hub's, from the last lookup that succeeded
  socklen_t address_length_ = 0;
  Clock::time_point next_resolve_{};  // no lookup starts before this
  std::vector<Dial> dials_;           // connects in flight
  DialPlan plan_;
  std::unique_ptr<StreamLink> link_;
  std::deque<std::vector<uint8_t>> held_;  // newest last, at most options_.held_datagrams
  Clock::time_point deadline_{};           // of the preamble awaited on a new connection
  uint64_t failures_this_outage_ = 0;
  std::string last_failure_;
  uint64_t dropped_queue_closed_ = 0;  // queue drops of links already closed
  TunnelClientCounters counters_;
  std::vector<std::string> events_;
};

}  // namespace mostar::udp_over_tcp
