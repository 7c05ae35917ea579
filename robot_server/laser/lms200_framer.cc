#include "robot_server/laser/lms200_framer.h"

#include <algorithm>

#include "robot_server/laser/lms200_crc.h"

namespace mostar::laser {

Lms200Framer::Lms200Framer(const Options& options) : options_(options) {
  options_.max_frame_bytes =
      std::clamp<size_t>(options_.max_frame_bytes, kLms200FrameOverheadBytes + 1, 65535 + 6);
}

bool Lms200Framer::AddressAccepted(uint8_t address) const {
  if (options_.direction == Direction::kRequests) return address < 0x80;
  const uint8_t expected = static_cast<uint8_t>(0x80 | (options_.device_address & 0x7F));
  if (address == expected) return true;
  return options_.accept_reply_address_0x81 && options_.device_address == 0 && address == 0x81;
}

void Lms200Framer::DiscardOne() {
  ++head_;
  ++stats_.bytes_discarded;
  if (!discarding_) {
    discarding_ = true;
    ++stats_.resyncs;
  }
}

Lms200Framer::Scan Lms200Framer::ScanAtHead(std::vector<FramerEvent>* events) {
  const size_t available = buffered_bytes();
  const uint8_t* p = buffer_.data() + head_;
  if (p[0] != kLms200Stx) {
    if (options_.direction == Direction::kReplies && (p[0] == kLms200Ack || p[0] == kLms200Nak)) {
      FramerEvent event;
      event.type = p[0] == kLms200Ack ? FramerEventType::kAck : FramerEventType::kNak;
      ++(p[0] == kLms200Ack ? stats_.acks : stats_.naks);
      events->push_back(std::move(event));
      ++head_;
      discarding_ = false;
      return Scan::kConsumed;
    }
    return Scan::kDiscardOne;
  }
  if (available < 2) return Scan::kNeedMore;
  if (!AddressAccepted(p[1])) return Scan::kDiscardOne;
  if (available < 4) return Scan::kNeedMore;
  const size_t length = static_cast<size_t>(p[2]) | (static_cast<size_t>(p[3]) << 8);
  const size_t min_length = options_.direction == Direction::kReplies ? 2 : 1;
  if (length < min_length || length + kLms200FrameOverheadBytes > options_.max_frame_bytes) {
    return Scan::kDiscardOne;
  }
  const size_t frame_bytes = length + kLms200FrameOverheadBytes;
  if (available < frame_bytes) return Scan::kNeedMore;
  const uint16_t expected_crc = Lms200Crc(p, length + 4);
  const uint16_t wire_crc =
      static_cast<uint16_t>(p[length + 4] | (static_cast<uint16_t>(p[length + 5]) << 8));
  if (expected_crc != wire_crc) {
    ++stats_.crc_errors;
    return Scan::kDiscardOne;
  }
  FramerEvent event;
  event.type = FramerEventType::kFrame;
  event.frame.address = p[1];
  event.frame.payload.assign(p + 4, p + 4 + length);
  events->push_back(std::move(event));
  ++stats_.frames;
  head_ += frame_bytes;
  discarding_ = false;
  return Scan::kConsumed;
}

void Lms200Framer::Push(const uint8_t* data, size_t size, std::vector<FramerEvent>* events) {
  if (size > 0) buffer_.insert(buffer_.end(), data, data + size);
  while (buffered_bytes() > 0) {
    const Scan scan = ScanAtHead(events);
    if (scan == Scan::kNeedMore) break;
    if (scan == Scan::kDiscardOne) DiscardOne();
  }
  Compact();
}

void Lms200Framer::AbandonPartial(std::vector<FramerEvent>* events) {
  while (buffered_bytes() > 0) {
    const Scan scan = ScanAtHead(events);
    if (scan == Scan::kNeedMore) ++stats_.partials_abandoned;
    if (scan != Scan::kConsumed) DiscardOne();
  }
  Compact();
}

void Lms200Framer::Reset() {
  if (buffered_bytes() > 0) {
    stats_.bytes_discarded += buffered_bytes();
    ++stats_.resyncs;
  }
  buffer_.clear();
  head_ = 0;
  discarding_ = false;
}

void Lms200Framer::Compact() {
  if (head_ == buffer_.size()) {
    buffer_.clear();
    head_ = 0;
  } else if (head_ > 4096) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(head_));
    head_ = 0;
  }
}

}  // namespace mostar::laser
