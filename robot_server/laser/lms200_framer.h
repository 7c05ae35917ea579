// Incremental LMS2xx telegram framer: bytes in, telegrams and ACK/NAK events out.
//
// Wire layout (both directions): STX(0x02) | ADR | LEN_lo LEN_hi | LEN bytes | CRC_lo CRC_hi.
// LEN counts the command/reply byte, its data and (in replies) the status byte. There is no
// ETX: STX, ACK and NAK values may occur inside a payload, so frames are delimited by LEN and
// confirmed by the CRC only.
//
// Resynchronisation contract: on any failure (address not accepted, LEN out of range, CRC
// mismatch, candidate abandoned) the framer discards exactly ONE byte and rescans, so a valid
// frame hidden inside garbage, a false start or a truncated frame is never lost. A lone ACK
// (0x06) or NAK (0x15) byte found between frames is reported as an event. Bytes that are none
// of these are discarded and counted.
//
// A candidate frame whose LEN announces more bytes than have arrived is held until they
// arrive. When the line has been quiet for longer than the LMS's maximum inter-byte gap
// inside a telegram (14 ms), the caller calls `AbandonPartial()`: held candidates are then
// known to be truncated (the LMS aborts a transmission when the host sends a request) and
// the buffered bytes are rescanned.
//
// Not thread-safe; one framer per byte stream direction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mostar::laser {

constexpr uint8_t kLms200Stx = 0x02;
constexpr uint8_t kLms200Ack = 0x06;
constexpr uint8_t kLms200Nak = 0x15;
// Largest telegram on the wire: 401 values at 0.25 deg with real-time indices (TL 10-16).
constexpr size_t kLms200MaxFrameBytes = 814;
// Header (STX, ADR, LEN_lo, LEN_hi) + CRC.
constexpr size_t kLms200FrameOverheadBytes = 6;

// One telegram with a valid CRC.
struct Lms200Frame {
  uint8_t address = 0;           // as on the wire: 0x80 | device address for replies
  std::vector<uint8_t> payload;  // LEN bytes: command/reply byte, data, [status byte]
  uint8_t command() const { return payload.empty() ? 0 : payload[0]; }
  size_t wire_bytes() const { return payload.size() + kLms200FrameOverheadBytes; }
};

enum class FramerEventType { kFrame, kAck, kNak };

struct FramerEvent {
  FramerEventType type = FramerEventType::kFrame;
  Lms200Frame frame;  // only for kFrame
};

struct FramerStats {
  uint64_t frames = 0;
  uint64_t acks = 0;
  uint64_t naks = 0;
  uint64_t crc_errors = 0;       // candidates with a plausible header and a wrong CRC
  uint64_t resyncs = 0;          // runs of discarded bytes (each ends at a valid item)
  uint64_t bytes_discarded = 0;  // bytes that belonged to no frame, ACK or NAK
  uint64_t partials_abandoned = 0;
};

class Lms200Framer {
 public:
  enum class Direction {
    kReplies,   // LMS -> host: address 0x80 | device address, status byte, LEN >= 2
    kRequests,  // host -> LMS: address 0x00..0x7F, LEN >= 1; ACK/NAK bytes are not expected
  };
  struct Options {
    Direction direction = Direction::kReplies;
    uint8_t device_address = 0;  // 0x00 (broadcast) .. 0x7F
    // Replies: also accept 0x81 (seen in SICK quick-manual examples) when talking to 0x00.
    bool accept_reply_address_0x81 = true;
    size_t max_frame_bytes = kLms200MaxFrameBytes;
  };

  Lms200Framer() : Lms200Framer(Options{}) {}
  explicit Lms200Framer(const Options& options);

  // Appends `size` bytes and the events they complete, in stream order, to `events`.
  void Push(const uint8_t* data, size_t size, std::vector<FramerEvent>* events);
  // The line went quiet: no held candidate can still be in flight. Rescans the buffer from
  // one byte after each held candidate; afterwards the buffer is empty.
  void AbandonPartial(std::vector<FramerEvent>* events);
  // Drops all buffered bytes (counted as discarded), e.g. after the host flushed its input.
  void Reset();

  size_t buffered_bytes() const { return buffer_.size() - head_; }
  // True when the buffer starts with an incomplete candidate frame.
  bool holds_partial() const { return buffered_bytes() > 0; }
  const FramerStats& stats() const { return stats_; }

 private:
  enum class Scan { kNeedMore, kConsumed, kDiscardOne };
  Scan ScanAtHead(std::vector<FramerEvent>* events);
  bool AddressAccepted(uint8_t address) const;
  void DiscardOne();
  void Compact();

  Options options_;
  std::vector<uint8_t> buffer_;
  size_t head_ = 0;
  bool discarding_ = false;
  FramerStats stats_;
};

}  // namespace mostar::laser
