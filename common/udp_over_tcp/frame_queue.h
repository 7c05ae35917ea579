// The tunnel's send queue towards one TCP connection: a few kilobytes of framed datagrams
// waiting for the socket. It never grows past its capacity: a datagram that does not fit
// pushes out the oldest frames not yet begun (UDP semantics: the newest data wins, a dropped
// datagram is repaired end to end or not at all), and every dropped datagram is counted. So
// commands, e-stop and scans wait behind at most `capacity_bytes` of video, never behind
// seconds of it. Not thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace mostar::udp_over_tcp {

class FrameQueue {
 public:
  // capacity_bytes: the most framed bytes held (each frame is the datagram + 2 bytes).
  explicit FrameQueue(size_t capacity_bytes) : capacity_bytes_(capacity_bytes) {}

  // Queues one datagram (1..kMaxDatagramBytes bytes, else it is counted as dropped). Returns
  // the number of datagrams dropped to make room (this one included when it can never fit).
  size_t Push(const uint8_t* datagram, size_t size);

  // The next bytes to write: the unwritten rest of the oldest frame (empty when none).
  const uint8_t* front_data() const;
  size_t front_size() const;
  // Marks `bytes` (at most front_size()) as written.
  void Consume(size_t bytes);

  // Drops everything (a new connection starts clean); the partly written frame is not
  // counted as dropped (its stream is gone).
  void Clear();

  bool empty() const { return frames_.empty(); }
  size_t bytes() const { return bytes_; }  // framed bytes held, unwritten parts only
  size_t frames() const { return frames_.size(); }
  uint64_t dropped() const { return dropped_; }

 private:
  size_t capacity_bytes_;
  std::deque<std::vector<uint8_t>> frames_;
  size_t front_written_ = 0;  // bytes of frames_.front() already written
  size_t bytes_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace mostar::udp_over_tcp
