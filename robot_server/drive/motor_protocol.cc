#include "robot_server/drive/motor_protocol.h"

#include <type_traits>

namespace mostar::drive {
namespace {

// Little-endian writer and reader over a payload.
class Writer {
 public:
  void U8(uint8_t v) { bytes_.push_back(v); }
  void U16(uint16_t v) {
    U8(static_cast<uint8_t>(v & 0xFF));
    U8(static_cast<uint8_t>(v >> 8));
  }
  void U32(uint32_t v) {
    U16(static_cast<uint16_t>(v & 0xFFFF));
    U16(static_cast<uint16_t>(v >> 16));
  }
  void I32(int32_t v) { U32(static_cast<uint32_t>(v)); }
  std::vector<uint8_t> Take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

class Reader {
 public:
  explicit Reader(const std::vector<uint8_t>& bytes) : bytes_(bytes) {}
  uint8_t U8() { return bytes_[pos_++]; }
  uint16_t U16() {
    const uint16_t lo = U8();
    const uint16_t hi = U8();
    return static_cast<uint16_t>(lo | (hi << 8));
  }
  uint32_t U32() {
    const uint32_t lo = U16();
    const uint32_t hi = U16();
    return lo | (hi << 16);
  }
  int32_t I32() { return static_cast<int32_t>(U32()); }

 private:
  const std::vector<uint8_t>& bytes_;
  size_t pos_ = 0;
};

// Payload size of each known type.
int PayloadSize(uint8_t type) {
  switch (static_cast<MessageType>(type)) {
    case MessageType::kSetVelocity:
      return 10;
    case MessageType::kStop:
      return 3;
    case MessageType::kHeartbeat:
      return 2;
    case MessageType::kEncoderReport:
      return 12;
    case MessageType::kStatus:
      return 7;
  }
  return -1;
}

}  // namespace

uint16_t Crc16CcittFalse(const uint8_t* data, size_t size, uint16_t crc) {
  for (size_t i = 0; i < size; ++i) {
    crc = static_cast<uint16_t>(crc ^ (static_cast<uint16_t>(data[i]) << 8));
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 0x8000) ? static_cast<uint16_t>((crc << 1) ^ 0x1021)
                           : static_cast<uint16_t>(crc << 1);
    }
  }
  return crc;
}

std::vector<uint8_t> EncodeFrame(MessageType type, const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> frame;
  frame.reserve(payload.size() + kFrameOverheadBytes);
  frame.push_back(kSync0);
  frame.push_back(kSync1);
  frame.push_back(static_cast<uint8_t>(type));
  frame.push_back(static_cast<uint8_t>(payload.size()));
  frame.insert(frame.end(), payload.begin(), payload.end());
  const uint16_t crc = Crc16CcittFalse(frame.data() + 2, frame.size() - 2);
  frame.push_back(static_cast<uint8_t>(crc & 0xFF));
  frame.push_back(static_cast<uint8_t>(crc >> 8));
  return frame;
}

MessageType TypeOf(const MotorMessage& message) {
  return std::visit(
      [](const auto& m) {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, SetVelocityMsg>) return MessageType::kSetVelocity;
        if constexpr (std::is_same_v<T, StopMsg>) return MessageType::kStop;
        if constexpr (std::is_same_v<T, HeartbeatMsg>) return MessageType::kHeartbeat;
        if constexpr (std::is_same_v<T, EncoderReportMsg>) return MessageType::kEncoderReport;
        if constexpr (std::is_same_v<T, StatusMsg>) return MessageType::kStatus;
      },
      message);
}

std::vector<uint8_t> EncodeMessage(const MotorMessage& message) {
  Writer w;
  std::visit(
      [&w](const auto& m) {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, SetVelocityMsg>) {
          w.U16(m.sequence);
          w.I32(m.left_ticks_per_s);
          w.I32(m.right_ticks_per_s);
        } else if constexpr (std::is_same_v<T, StopMsg>) {
          w.U16(m.sequence);
          w.U8(m.clear_faults ? 1 : 0);
        } else if constexpr (std::is_same_v<T, HeartbeatMsg>) {
          w.U16(m.sequence);
        } else if constexpr (std::is_same_v<T, EncoderReportMsg>) {
          w.U32(m.board_time_us);
          w.U32(m.left_count);
          w.U32(m.right_count);
        } else if constexpr (std::is_same_v<T, StatusMsg>) {
          w.U8(static_cast<uint8_t>(m.state));
          w.U16(m.fault_flags);
          w.U16(m.battery_mv);
          w.U16(m.last_sequence);
        }
      },
      message);
  return EncodeFrame(TypeOf(message), w.Take());
}

bool DecodeMessage(const RawFrame& frame, MotorMessage* message, std::string* error) {
  const int expected = PayloadSize(frame.type);
  if (expected < 0) {
    *error = "unknown message type " + std::to_string(frame.type);
    return false;
  }
  if (frame.payload.size() != static_cast<size_t>(expected)) {
    *error = "message type " + std::to_string(frame.type) + " has " +
             std::to_string(frame.payload.size()) + " payload bytes, expected " +
             std::to_string(expected);
    return false;
  }
  Reader r(frame.payload);
  switch (static_cast<MessageType>(frame.type)) {
    case MessageType::kSetVelocity: {
      SetVelocityMsg m;
      m.sequence = r.U16();
      m.left_ticks_per_s = r.I32();
      m.right_ticks_per_s = r.I32();
      *message = m;
      return true;
    }
    case MessageType::kStop: {
      StopMsg m;
      m.sequence = r.U16();
      const uint8_t flags = r.U8();
      if (flags > 1) {
        *error = "stop flags " + std::to_string(flags) + " has unknown bits";
        return false;
      }
      m.clear_faults = flags == 1;
      *message = m;
      return true;
    }
    case MessageType::kHeartbeat: {
      HeartbeatMsg m;
      m.sequence = r.U16();
      *message = m;
      return true;
    }
    case MessageType::kEncoderReport: {
      EncoderReportMsg m;
      m.board_time_us = r.U32();
      m.left_count = r.U32();
      m.right_count = r.U32();
      *message = m;
      return true;
    }
    case MessageType::kStatus: {
      StatusMsg m;
      const uint8_t state = r.U8();
      if (state > static_cast<uint8_t>(BoardState::kFault)) {
        *error = "board state " + std::to_string(state) + " is unknown";
        return false;
      }
      m.state = static_cast<BoardState>(state);
      m.fault_flags = r.U16();
      m.battery_mv = r.U16();
      m.last_sequence = r.U16();
      *message = m;
      return true;
    }
  }
  *error = "unknown message type";
  return false;
}

void MotorFrameDecoder::Push(const uint8_t* data, size_t size) {
  buffer_.insert(buffer_.end(), data, data + size);
}

std::optional<RawFrame> MotorFrameDecoder::Next() {
  while (true) {
    // Find the sync pair at the front.
    while (!buffer_.empty() &&
           !(buffer_[0] == kSync0 && (buffer_.size() < 2 || buffer_[1] == kSync1))) {
      buffer_.pop_front();
      ++stats_.discarded_bytes;
    }
    if (buffer_.size() < 4) return std::nullopt;
    const size_t length = buffer_[3];
    if (length > kMaxPayloadBytes) {
      ++stats_.bad_lengths;
      buffer_.pop_front();
      ++stats_.discarded_bytes;
      continue;
    }
    const size_t frame_size = length + kFrameOverheadBytes;
    if (buffer_.size() < frame_size) return std::nullopt;
    uint8_t bytes[kMaxPayloadBytes + 2];
    for (size_t i = 0; i < length + 2; ++i) bytes[i] = buffer_[2 + i];
    const uint16_t crc = Crc16CcittFalse(bytes, length + 2);
    const uint16_t received = static_cast<uint16_t>(
        buffer_[frame_size - 2] | (static_cast<uint16_t>(buffer_[frame_size - 1]) << 8));
    if (crc != received) {
      ++stats_.crc_errors;
      buffer_.pop_front();
      ++stats_.discarded_bytes;
      continue;
    }
    RawFrame frame;
    frame.type = bytes[0];
    frame.payload.assign(bytes + 2, bytes + 2 + length);
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(frame_size));
    ++stats_.frames;
    return frame;
  }
}

}  // namespace mostar::drive
