// One tunnel connection: a connected, non-blocking stream socket (TCP in the program, a
// socketpair in tests) carrying framed datagrams both ways (frame_codec.h). Sending never
// blocks and never queues more than the FrameQueue's capacity in user space plus
// max_unsent_bytes in the kernel (bytes written but not yet sent, Linux SIOCOUTQNSD; with
// TCP_NOTSENT_LOWAT set to the same value poll() reports the socket writable only below it).
// Whatever does not fit is dropped and counted. Owns the socket. Not thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/udp_over_tcp/frame_codec.h"
#include "common/udp_over_tcp/frame_queue.h"

namespace mostar::udp_over_tcp {

struct StreamLinkOptions {
  size_t max_datagram_bytes = 4096;  // larger received frames are a protocol error
  // User-space send queue (framed bytes): holds one burst (a stereo pair's fragments arrive
  // together), about 65 ms at 8 Mbit/s.
  size_t queue_bytes = 64 * 1024;
  size_t max_unsent_bytes = 16 * 1024;  // kernel bytes written but not sent yet
};

struct StreamLinkCounters {
  uint64_t datagrams_sent = 0;      // queued towards the stream
  uint64_t datagrams_received = 0;  // decoded from the stream
  uint64_t datagrams_dropped = 0;   // pushed out of (or never fitting in) the send queue
  uint64_t bytes_written = 0;
  uint64_t bytes_read = 0;
};

class StreamLink {
 public:
  // Takes ownership of `fd`, a connected stream socket; makes it non-blocking and queues the
  // preamble.
  StreamLink(int fd, const StreamLinkOptions& options);
  ~StreamLink();
  StreamLink(const StreamLink&) = delete;
  StreamLink& operator=(const StreamLink&) = delete;

  int fd() const { return fd_; }

  // Queues one datagram; a full queue drops the oldest (counted).
  void Send(const uint8_t* datagram, size_t size);

  // Reads what is available (a bounded number of reads per call) and hands each datagram to
  // on_datagram. Returns false with *error on end of stream, a socket error or a protocol
  // error: the caller then destroys the link.
  bool OnReadable(const FrameDecoder::DatagramFn& on_datagram, std::string* error);

  // Writes queued bytes within the unsent-bytes budget. False with *error on a socket error.
  bool OnWritable(std::string* error);

  // True when queued bytes wait for the socket (poll for POLLOUT).
  bool wants_write() const { return !queue_.empty() || preamble_left_ > 0; }
  bool preamble_received() const { return decoder_.preamble_seen(); }
  const StreamLinkCounters& counters() const { return counters_; }

 private:
  size_t WriteBudget() const;

  int fd_;
  StreamLinkOptions options_;
  FrameDecoder decoder_;
  FrameQueue queue_;
  size_t preamble_left_;
  StreamLinkCounters counters_;
};

// Unsent bytes in the kernel's send queue of a TCP socket; 0 where the query is not supported
// (other socket types).
size_t UnsentBytes(int fd);

}  // namespace mostar::udp_over_tcp
