#include "common/udp_over_tcp/stream_link.h"

#include <fcntl.h>
#include <linux/sockios.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace mostar::udp_over_tcp {
namespace {

constexpr int kMaxReadsPerCall = 16;  // then the loop serves the other sockets
constexpr size_t kReadBytes = 64 * 1024;

}  // namespace

size_t UnsentBytes(int fd) {
  int unsent = 0;
  if (ioctl(fd, SIOCOUTQNSD, &unsent) != 0 || unsent < 0) return 0;
  return static_cast<size_t>(unsent);
}

StreamLink::StreamLink(int fd, const StreamLinkOptions& options)
    : fd_(fd),
      options_(options),
      decoder_(options.max_datagram_bytes),
      queue_(options.queue_bytes),
      preamble_left_(kPreamble.size()) {
  const int flags = fcntl(fd_, F_GETFL, 0);
  if (flags >= 0) fcntl(fd_, F_SETFL, flags | O_NONBLOCK);
}

StreamLink::~StreamLink() {
  if (fd_ >= 0) close(fd_);
}

void StreamLink::Send(const uint8_t* datagram, size_t size) {
  ++counters_.datagrams_sent;
  counters_.datagrams_dropped += queue_.Push(datagram, size);
}

bool StreamLink::OnReadable(const FrameDecoder::DatagramFn& on_datagram, std::string* error) {
  static thread_local uint8_t buffer[kReadBytes];
  const FrameDecoder::DatagramFn count_and_deliver = [&](const uint8_t* data, size_t size) {
    ++counters_.datagrams_received;
    on_datagram(data, size);
  };
  for (int i = 0; i < kMaxReadsPerCall; ++i) {
    const ssize_t n = recv(fd_, buffer, sizeof(buffer), MSG_DONTWAIT);
    if (n == 0) {
      *error = "connection closed by the peer";
      return false;
    }
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) return true;
      if (errno == EINTR) continue;
      *error = std::string("receive failed: ") + std::strerror(errno);
      return false;
    }
    counters_.bytes_read += static_cast<uint64_t>(n);
    if (!decoder_.Feed(buffer, static_cast<size_t>(n), count_and_deliver, error)) return false;
    if (static_cast<size_t>(n) < sizeof(buffer)) return true;
  }
  return true;
}

size_t StreamLink::WriteBudget() const {
  const size_t unsent = UnsentBytes(fd_);
  return unsent >= options_.max_unsent_bytes ? 0 : options_.max_unsent_bytes - unsent;
}

bool StreamLink::OnWritable(std::string* error) {
  size_t budget = WriteBudget();
  while (budget > 0 && wants_write()) {
    const uint8_t* data;
    size_t size;
    if (preamble_left_ > 0) {
      data = kPreamble.data() + (kPreamble.size() - preamble_left_);
      size = preamble_left_;
    } else {
      data = queue_.front_data();
      size = queue_.front_size();
    }
    size = std::min(size, budget);
    const ssize_t n = send(fd_, data, size, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) return true;
      if (errno == EINTR) continue;
      *error = std::string("send failed: ") + std::strerror(errno);
      return false;
    }
    const size_t written = static_cast<size_t>(n);
    counters_.bytes_written += written;
    budget -= written;
    if (preamble_left_ > 0) {
      preamble_left_ -= written;
    } else {
      queue_.Consume(written);
    }
  }
  return true;
}

}  // namespace mostar::udp_over_tcp
