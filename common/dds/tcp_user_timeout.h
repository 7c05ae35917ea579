// Bounds how long a TCP peer that stopped reading can block this process's DDS sends.
//
// Fast DDS 2.9 writes to a TCP connection with a blocking send (no timeout) while holding the
// writer's lock. A peer that vanished (link cut, no FIN/RST) or stopped reading (frozen
// process, zero window) therefore stalls every reader of that writer, other operators
// included, until the kernel gives up on the connection: about 15 minutes by default. The
// transport exposes no socket option for this, so TcpUserTimeoutGuard sets the Linux socket
// option TCP_USER_TIMEOUT on every TCP socket of this process (Fast DDS' listeners, accepted
// and dialled connections): data left unacknowledged, or unsent behind a zero window, for
// longer than the timeout makes the kernel drop the connection. The blocked send then fails,
// Fast DDS closes the channel and a TCP client dials again once its peer answers.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace mostar::dds {

// Sets TCP_USER_TIMEOUT to `timeout_ms` (> 0) on every IPv4/IPv6 TCP socket of this process
// that does not have that value yet. Returns how many sockets were changed.
int ApplyTcpUserTimeout(int timeout_ms);

// Applies ApplyTcpUserTimeout every `scan_period` on a thread of its own (new connections get
// the option within one period; accepted connections inherit it from the listener at once).
class TcpUserTimeoutGuard {
 public:
  TcpUserTimeoutGuard(int timeout_ms, std::chrono::milliseconds scan_period);
  ~TcpUserTimeoutGuard();
  TcpUserTimeoutGuard(const TcpUserTimeoutGuard&) = delete;
  TcpUserTimeoutGuard& operator=(const TcpUserTimeoutGuard&) = delete;

  int timeout_ms() const { return timeout_ms_; }
  // Sockets given the option so far.
  int sockets_set() const { return sockets_set_.load(); }

 private:
  const int timeout_ms_;
  std::atomic<int> sockets_set_{0};
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace mostar::dds
