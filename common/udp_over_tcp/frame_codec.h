// The byte stream of the UDP-over-TCP tunnel (mostar_wg_tcp): each side first sends the
// 4-byte preamble "MWG1", then every UDP datagram as one frame: its length as 2 bytes
// big-endian (1..65535) followed by the datagram. A length of 0, a length above the
// receiver's limit, or a wrong preamble is a protocol error: the receiver reports it and
// resets the connection (it never tries to resynchronise inside a stream).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace mostar::udp_over_tcp {

inline constexpr std::array<uint8_t, 4> kPreamble = {'M', 'W', 'G', '1'};
inline constexpr size_t kLengthBytes = 2;
inline constexpr size_t kMaxDatagramBytes = 65535;  // what the 2-byte length can carry

// Appends one frame (length prefix + datagram) to *out. Returns false (and appends nothing)
// when size is 0 or above kMaxDatagramBytes.
bool AppendFrame(const uint8_t* datagram, size_t size, std::vector<uint8_t>* out);

// Splits a received byte stream into datagrams, whatever the chunking of the reads (a frame
// split over reads, several frames in one read). Memory: at most kLengthBytes +
// max_datagram_bytes are buffered. Not thread-safe.
class FrameDecoder {
 public:
  using DatagramFn = std::function<void(const uint8_t* datagram, size_t size)>;

  // max_datagram_bytes: the largest accepted datagram, 1..kMaxDatagramBytes (clamped).
  explicit FrameDecoder(size_t max_datagram_bytes);

  // Consumes `size` bytes; calls on_datagram for each complete datagram, in order (the pointer
  // is valid only during the call). Returns false with *error naming the violation at the
  // first protocol error; the decoder then stays failed and the stream must be closed.
  bool Feed(const uint8_t* data, size_t size, const DatagramFn& on_datagram, std::string* error);

  bool preamble_seen() const { return preamble_seen_; }
  bool failed() const { return failed_; }
  size_t buffered_bytes() const { return partial_.size(); }

 private:
  bool Fail(std::string message, std::string* error);

  size_t max_datagram_bytes_;
  bool preamble_seen_ = false;
  bool failed_ = false;
  size_t preamble_bytes_ = 0;     // bytes of the preamble matched so far
  std::vector<uint8_t> partial_;  // the incomplete frame at the end of the last Feed
};

}  // namespace mostar::udp_over_tcp
