#include "common/udp_over_tcp/tunnel_client.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <thread>
#include <utility>

namespace mostar::udp_over_tcp {
namespace {

constexpr int kMaxUdpReadsPerPoll = 256;  // then the stream gets its turn

int MillisUntil(std::chrono::steady_clock::time_point t,
                std::chrono::steady_clock::time_point now) {
  return static_cast<int>(
      std::max<int64_t>(0, std::chrono::duration_cast<std::chrono::milliseconds>(t - now).count()));
}

}  // namespace

// A name lookup on a detached thread: the loop polls `done`; an abandoned lookup finishes (or
// the process ends) on its own.
struct TunnelClient::Resolve {
  std::atomic<bool> done{false};
  sockaddr_storage address{};
  socklen_t length = 0;
  std::string error;
};

namespace {

DialPlanOptions PlanOptions(const TunnelClientOptions& o) {
  DialPlanOptions plan;
  plan.interval = std::chrono::milliseconds(std::max(1, o.dial_interval_ms));
  plan.max_in_flight = std::max(1, o.connect_timeout_ms / std::max(1, o.dial_interval_ms) + 1);
  plan.initial_backoff = std::chrono::milliseconds(o.initial_backoff_ms);
  plan.max_backoff = std::chrono::milliseconds(o.max_backoff_ms);
  return plan;
}

constexpr auto kResolveAgain = std::chrono::seconds(30);  // while not connected

}  // namespace

TunnelClient::TunnelClient(TunnelClientOptions options)
    : options_(std::move(options)), plan_(PlanOptions(options_)) {}

TunnelClient::~TunnelClient() {
  if (udp_fd_ >= 0) close(udp_fd_);
  CloseDials();
}

bool TunnelClient::Open(std::string* error) {
  sockaddr_in listen{};
  if (!ParseIpv4Endpoint(options_.listen, &listen, error, true)) {
    *error = "--listen: " + *error;
    return false;
  }
  if (!SplitHostPort(options_.hub, &hub_host_, &hub_port_, error)) {
    *error = "--hub: " + *error;
    return false;
  }
  if (options_.connect_timeout_ms <= 0 || options_.initial_backoff_ms <= 0 ||
      options_.dial_interval_ms <= 0 || options_.max_backoff_ms < options_.initial_backoff_ms) {
    *error = "timeouts must be positive and the maximum backoff at least the initial one";
    return false;
  }
  if (options_.held_datagrams < 0 || options_.held_datagrams > 1024) {
    *error = "held datagrams must be 0..1024";
    return false;
  }
  udp_fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (udp_fd_ < 0 || bind(udp_fd_, reinterpret_cast<const sockaddr*>(&listen), sizeof(listen))) {
    *error = "cannot bind UDP " + options_.listen + ": " + std::strerror(errno);
    return false;
  }
  port_ = BoundPort(udp_fd_);
  return true;
}

TunnelClientCounters TunnelClient::counters() const {
  TunnelClientCounters c = counters_;
  c.dropped_queue = dropped_queue_closed_ + (link_ ? link_->counters().datagrams_dropped : 0);
  return c;
}

std::vector<std::string> TunnelClient::TakeEvents() { return std::exchange(events_, {}); }

std::string LookUpWithGetaddrinfo(const std::string& host, int port, sockaddr_storage* address,
                                  socklen_t* length) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* result = nullptr;
  const int status = getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &result);
  std::string error;
  if (status != 0 || result == nullptr) {
    error = "cannot resolve " + host + ": " + gai_strerror(status);
  } else {
    std::memcpy(address, result->ai_addr, result->ai_addrlen);
    *length = result->ai_addrlen;
  }
  if (result != nullptr) freeaddrinfo(result);
  return error;
}

void TunnelClient::StartResolve() {
  auto job = std::make_shared<Resolve>();
  resolve_ = job;
  ++counters_.lookups;
  std::thread([job, lookup = options_.lookup, host = hub_host_, port = hub_port_] {
    job->error = lookup(host, port, &job->address, &job->length);
    job->done.store(true, std::memory_order_release);
  }).detach();
}

void TunnelClient::FinishResolve(Clock::time_point now) {
  const auto job = std::exchange(resolve_, nullptr);
  next_resolve_ = now + kResolveAgain;
  if (!job->error.empty()) {
    if (address_length_ == 0) {  // nothing to dial yet: an answered failure, backed off
      Failed(job->error);
      next_resolve_ = now + plan_.Answered(now);
    }
    return;
  }
  address_ = job->address;
  address_length_ = job->length;
}

void TunnelClient::StartDial(Clock::time_point now) {
  plan_.Started(now);
  ++counters_.dials;
  const int fd = socket(address_.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    Failed(std::string("socket: ") + std::strerror(errno));
    plan_.Answered(now);
    return;
  }
  std::string warning, error;
  if (!ConfigureTcpSocket(fd, options_.tcp, &warning, &error)) {
    close(fd);
    Failed(error);
    plan_.Answered(now);
    return;
  }
  if (!warning.empty() && counters_.dials == 1) events_.push_back(warning);
  if (connect(fd, reinterpret_cast<const sockaddr*>(&address_), address_length_) != 0 &&
      errno != EINPROGRESS) {
    const int error_number = errno;
    close(fd);
    Failed("connect to " + options_.hub + ": " + std::strerror(error_number));
    plan_.Answered(now);
    return;
  }
  dials_.push_back({fd, now + std::chrono::milliseconds(options_.connect_timeout_ms)});
}

void TunnelClient::FinishDial(size_t index, Clock::time_point now) {
  const int fd = dials_[index].fd;
  dials_.erase(dials_.begin() + static_cast<std::ptrdiff_t>(index));
  int status = 0;
  socklen_t length = sizeof(status);
  if (getsockopt(fd, SOL_SOCKET, SO_ERROR, &status, &length) != 0) status = errno;
  if (status != 0) {
    close(fd);
    Failed("connect to " + options_.hub + " failed: " + std::strerror(status));
    plan_.Answered(now);
    return;
  }
  CloseDials();  // the first to connect wins
  link_ = std::make_unique<StreamLink>(fd, options_.link);
  // The preamble must arrive within the connect timeout, counted from now.
  deadline_ = now + std::chrono::milliseconds(options_.connect_timeout_ms);
}

void TunnelClient::CloseDials() {
  for (const Dial& dial : dials_) close(dial.fd);
  dials_.clear();
}

void TunnelClient::Failed(const std::string& why) {
  ++counters_.failures;
  last_failure_ = why;
  // Said once per outage (a dead path fails a dial every interval); the count comes with
  // "connected" and in the periodic counters.
  if (failures_this_outage_++ == 0) events_.push_back(why + "; dialling again");
}

void TunnelClient::Drop(const std::string& why, Clock::time_point now) {
  if (link_) {
    dropped_queue_closed_ += link_->counters().datagrams_dropped;
    link_.reset();
  }
  Failed(why);
  plan_.Answered(now);
}

void TunnelClient::Deliver(const uint8_t* datagram, size_t size) {
  if (!have_sender_) {
    ++counters_.dropped_no_sender;
    return;
  }
  // A full local socket buffer drops the datagram, as UDP would.
  if (sendto(udp_fd_, datagram, size, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&sender_),
             sizeof(sender_)) == static_cast<ssize_t>(size)) {
    ++counters_.udp_out;
  }
}

void TunnelClient::ReadUdp() {
  static thread_local uint8_t buffer[kMaxDatagramBytes];
  for (int i = 0; i < kMaxUdpReadsPerPoll; ++i) {
    sockaddr_in from{};
    socklen_t from_length = sizeof(from);
    const ssize_t n = recvfrom(udp_fd_, buffer, sizeof(buffer), MSG_DONTWAIT,
                               reinterpret_cast<sockaddr*>(&from), &from_length);
    if (n < 0) return;  // EAGAIN, or an ICMP error from an earlier send: nothing to read
    ++counters_.udp_in;
    sender_ = from;
    have_sender_ = true;
    if (connected()) {
      // Straight on to the socket while its budget lasts: the queue holds only the excess.
      link_->Send(buffer, static_cast<size_t>(n));
      std::string error;
      if (!link_->OnWritable(&error)) {
        Drop("connection to " + options_.hub + " ended: " + error, Clock::now());
      }
    } else if (options_.held_datagrams > 0) {
      held_.emplace_back(buffer, buffer + n);
      if (held_.size() > static_cast<size_t>(options_.held_datagrams)) {
        held_.pop_front();
        ++counters_.dropped_no_link;
      }
    } else {
      ++counters_.dropped_no_link;
    }
  }
}

void TunnelClient::SendHeld(Clock::time_point now) {
  if (held_.empty()) return;
  for (const std::vector<uint8_t>& datagram : held_) {
    link_->Send(datagram.data(), datagram.size());
    ++counters_.held_sent;
  }
  held_.clear();
  std::string error;
  if (!link_->OnWritable(&error)) Drop("connection to " + options_.hub + " ended: " + error, now);
}

void TunnelClient::Poll(int timeout_ms) {
  auto now = Clock::now();
  if (!connected() && !resolve_ && now >= next_resolve_) StartResolve();
  if (!link_ && address_length_ > 0 && plan_.ShouldDial(now, static_cast<int>(dials_.size()))) {
    StartDial(now);
  }

  std::vector<pollfd> fds;
  fds.push_back({udp_fd_, POLLIN, 0});
  if (link_) {
    fds.push_back(
        {link_->fd(), static_cast<short>(POLLIN | (link_->wants_write() ? POLLOUT : 0)), 0});
  }
  for (const Dial& dial : dials_) fds.push_back({dial.fd, POLLOUT, 0});
  int wait_ms = timeout_ms;
  if (resolve_) wait_ms = std::min(wait_ms, 20);  // the lookup has no descriptor to poll
  if (!resolve_ && address_length_ == 0)
    wait_ms = std::min(wait_ms, MillisUntil(next_resolve_, now));
  if (link_ && !connected()) wait_ms = std::min(wait_ms, MillisUntil(deadline_, now));
  for (const Dial& dial : dials_) wait_ms = std::min(wait_ms, MillisUntil(dial.deadline, now));
  if (!link_ && address_length_ > 0)
    wait_ms = std::min(wait_ms, MillisUntil(plan_.next_dial(), now));
  if (poll(fds.data(), fds.size(), wait_ms) < 0 && errno != EINTR) return;
  now = Clock::now();

  if (resolve_ && resolve_->done.load(std::memory_order_acquire)) FinishResolve(now);
  // Dials: the first that connects wins (FinishDial closes the rest); others fail or time out.
  const size_t first_dial = link_ ? 2 : 1;
  for (size_t k = fds.size(); k-- > first_dial;) {
    if (link_ || k - first_dial >= dials_.size()) continue;
    if (fds[k].revents & (POLLOUT | POLLERR | POLLHUP)) FinishDial(k - first_dial, now);
  }
  for (size_t k = dials_.size(); k-- > 0;) {
    if (now >= dials_[k].deadline) {
      close(dials_[k].fd);
      dials_.erase(dials_.begin() + static_cast<std::ptrdiff_t>(k));
      Failed("connect to " + options_.hub + " took longer than " +
             std::to_string(options_.connect_timeout_ms) + " ms");  // silent path: no backoff
    }
  }
  if (link_ && first_dial == 2 && fds[1].revents != 0) {
    const bool was_connected = connected();
    std::string error;
    bool ok = true;
    if (fds[1].revents & (POLLIN | POLLERR | POLLHUP)) {
      ok = link_->OnReadable([this](const uint8_t* d, size_t s) { Deliver(d, s); }, &error);
    }
    if (ok && (fds[1].revents & POLLOUT)) ok = link_->OnWritable(&error);
    if (!ok) {
      Drop("connection to " + options_.hub + " ended: " + error, now);
    } else if (!was_connected && connected()) {
      ++counters_.connects;
      plan_.Connected();
      events_.push_back("connected to " + options_.hub +
                        (failures_this_outage_ == 0
                             ? std::string()
                             : " after " + std::to_string(failures_this_outage_) +
                                   " failed dials (the last: " + last_failure_ + ")"));
      failures_this_outage_ = 0;
      SendHeld(now);
    }
  }
  if (link_ && !connected() && now >= deadline_) {
    Drop("the hub's preamble took longer than " + std::to_string(options_.connect_timeout_ms) +
             " ms",
         now);
  }

  if (fds[0].revents & POLLIN) ReadUdp();
  if (link_ && link_->wants_write()) {  // send what just came in without another poll round
    std::string error;
    if (!link_->OnWritable(&error)) Drop("connection to " + options_.hub + " ended: " + error, now);
  }
}

}  // namespace mostar::udp_over_tcp
