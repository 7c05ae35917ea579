#include "common/record/recording_format.h"

#include <array>

namespace mostar::record {
namespace {

std::array<uint32_t, 256> MakeCrcTable() {
  std::array<uint32_t, 256> table{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

}  // namespace

uint32_t Crc32(const void* data, size_t size, uint32_t crc) {
  static const std::array<uint32_t, 256> kTable = MakeCrcTable();
  const auto* bytes = static_cast<const uint8_t*>(data);
  crc = ~crc;
  for (size_t i = 0; i < size; ++i) crc = kTable[(crc ^ bytes[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

void AppendFrame(const std::string& bytes, std::string* out) {
  uint64_t length = bytes.size();
  do {
    uint8_t b = static_cast<uint8_t>(length & 0x7Fu);
    length >>= 7;
    if (length != 0) b |= 0x80u;
    out->push_back(static_cast<char>(b));
  } while (length != 0);
  out->append(bytes);
  const uint32_t crc = Crc32(bytes.data(), bytes.size());
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<char>((crc >> (8 * i)) & 0xFFu));
}

int ParseVarint(const uint8_t* data, size_t size, uint64_t* value) {
  uint64_t result = 0;
  for (size_t i = 0; i < 10; ++i) {
    if (i >= size) return 0;
    const uint64_t b = data[i];
    if (i == 9 && b > 1) return -1;  // more than 64 bits
    result |= (b & 0x7Fu) << (7 * i);
    if ((b & 0x80u) == 0) {
      *value = result;
      return static_cast<int>(i + 1);
    }
  }
  return -1;
}

std::string TopicName(const RecordedMessage& message) {
  switch (message.kind()) {
    case RecordKind::kImage:
      return std::get<RecordedImage>(message.payload).eye == Eye::kLeft ? "camera/left"
                                                                        : "camera/right";
    case RecordKind::kScan:
      return "scan";
    case RecordKind::kOdometry:
      return "odom";
    case RecordKind::kVelocityCommand:
      return "cmd_vel";
    case RecordKind::kEmergencyStop:
      return "estop";
    case RecordKind::kControlRequest:
      return "control/request";
    case RecordKind::kControlLease:
      return "control/lease";
    case RecordKind::kHealth:
      return "health";
    case RecordKind::kSonar:
      return "sonar";
    case RecordKind::kBumpers:
      return "bumpers";
  }
  return "?";
}

}  // namespace mostar::record
