// Binary protocol between robot_server and the motor + encoder board (docs/motor_protocol.md is
// the contract for its firmware). Pure code: bytes in, typed messages out, and back.
//
// Frame: 0xAA 0x55 | type u8 | length u8 | payload (length bytes) | crc u16
//   - crc: CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor) over
//     type, length and payload; sent little-endian like every multi-byte field.
//   - length <= kMaxPayloadBytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace mostar::drive {

constexpr uint8_t kSync0 = 0xAA;
constexpr uint8_t kSync1 = 0x55;
constexpr size_t kMaxPayloadBytes = 32;
constexpr size_t kFrameOverheadBytes = 6;  // sync(2) + type + length + crc(2)

enum class MessageType : uint8_t {
  // Host -> board.
  kSetVelocity = 0x01,
  kStop = 0x02,
  kHeartbeat = 0x03,  // both directions; the board echoes the host's sequence
  // Board -> host.
  kEncoderReport = 0x10,
  kStatus = 0x11,
};

// Wheel speed set-points in encoder ticks per second (positive = the wheel drives the robot
// forward). The board runs its speed loops until the next SetVelocity or Stop, and stops by
// itself when no SetVelocity arrives for 300 ms.
struct SetVelocityMsg {
  uint16_t sequence = 0;
  int32_t left_ticks_per_s = 0;
  int32_t right_ticks_per_s = 0;
};

// Brake both wheels now. `clear_faults` also clears latched fault flags.
struct StopMsg {
  uint16_t sequence = 0;
  bool clear_faults = false;
};

struct HeartbeatMsg {
  uint16_t sequence = 0;
};

// Raw free-running counters, sampled together. Only the low `counter_bits` (board specific,
// from the configuration) are significant; they wrap around.
struct EncoderReportMsg {
  uint32_t board_time_us = 0;  // board clock, wraps after ~71 minutes
  uint32_t left_count = 0;
  uint32_t right_count = 0;
};

enum class BoardState : uint8_t { kStopped = 0, kDriving = 1, kFault = 2 };

// Fault flag bits of StatusMsg::fault_flags.
enum FaultFlag : uint16_t {
  kFaultOvercurrentLeft = 1u << 0,
  kFaultOvercurrentRight = 1u << 1,
  kFaultCommandTimeout = 1u << 2,  // stopped because no SetVelocity for 300 ms (not latched)
  kFaultUndervoltage = 1u << 3,
  kFaultDriver = 1u << 4,
  kFaultEncoder = 1u << 5,
  kFaultBadFrames = 1u << 6,  // CRC or length errors seen since the last status
};

struct StatusMsg {
  BoardState state = BoardState::kStopped;
  uint16_t fault_flags = 0;
  uint16_t battery_mv = 0;
  uint16_t last_sequence = 0;  // of the last SetVelocity or Stop applied
};

using MotorMessage =
    std::variant<SetVelocityMsg, StopMsg, HeartbeatMsg, EncoderReportMsg, StatusMsg>;

// CRC-16/CCITT-FALSE. Check value: "123456789" -> 0x29B1.
uint16_t Crc16CcittFalse(const uint8_t* data, size_t size, uint16_t crc = 0xFFFF);

// A complete frame.
std::vector<uint8_t> EncodeFrame(MessageType type, const std::vector<uint8_t>& payload);
std::vector<uint8_t> EncodeMessage(const MotorMessage& message);
MessageType TypeOf(const MotorMessage& message);

// A frame whose sync, length and CRC checked out; the payload is not interpreted yet.
struct RawFrame {
  uint8_t type = 0;
  std::vector<uint8_t> payload;
};

// Interprets a frame. False with a message for an unknown type or a wrong payload length.
bool DecodeMessage(const RawFrame& frame, MotorMessage* message, std::string* error);

struct MotorDecoderStats {
  uint64_t frames = 0;  // frames with a good CRC
  uint64_t crc_errors = 0;
  uint64_t bad_lengths = 0;      // length byte above kMaxPayloadBytes
  uint64_t discarded_bytes = 0;  // bytes skipped while looking for sync
};

// Streaming frame extractor. Resynchronises on garbage: after a bad CRC or an impossible
// length it drops one byte only and searches the next sync, so a valid frame that starts
// inside rejected bytes is never lost. Buffers at most one frame plus the bytes pushed since.
// Not thread-safe.
class MotorFrameDecoder {
 public:
  void Push(const uint8_t* data, size_t size);
  void Push(const std::vector<uint8_t>& data) { Push(data.data(), data.size()); }
  // The next complete frame, or nullopt when more bytes are needed.
  std::optional<RawFrame> Next();
  const MotorDecoderStats& stats() const { return stats_; }
  size_t buffered_bytes() const { return buffer_.size(); }

 private:
  std::deque<uint8_t> buffer_;
  MotorDecoderStats stats_;
};

}  // namespace mostar::drive
