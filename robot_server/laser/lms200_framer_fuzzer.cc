// libFuzzer target: arbitrary bytes through the framer and every decoder must never crash,
// hang or read out of bounds, and every frame reported must carry a valid CRC.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "robot_server/laser/lms200_crc.h"
#include "robot_server/laser/lms200_framer.h"
#include "robot_server/laser/lms200_telegrams.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mostar::laser;
  if (size == 0) return 0;
  // The first byte chooses the read chunk size, so splits are fuzzed too.
  const size_t chunk = 1 + data[0] % 64;
  Lms200Framer framer;
  std::vector<FramerEvent> events;
  for (size_t pos = 1; pos < size; pos += chunk) {
    framer.Push(data + pos, std::min(chunk, size - pos), &events);
  }
  framer.AbandonPartial(&events);
  if (framer.buffered_bytes() != 0) std::abort();
  std::string error;
  for (const FramerEvent& event : events) {
    if (event.type != FramerEventType::kFrame) continue;
    const std::vector<uint8_t> wire = BuildReplyTelegram(event.frame.address, event.frame.payload);
    if (Lms200Crc(wire.data(), wire.size() - 2) !=
        static_cast<uint16_t>(wire[wire.size() - 2] | (wire.back() << 8))) {
      std::abort();
    }
    Lms200MeasuredValues values;
    for (uint8_t mode : {0x00, 0x03, 0x05, 0x0F, 0x3F}) {
      for (bool indices : {false, true}) {
        if (DecodeScanReply(event.frame, {mode, indices}, &values, &error)) {
          mostar::LaserScan scan;
          Lms200BeamCounts counts;
          if (ToLaserScan(values, mode, &scan, &counts, &error) &&
              scan.ranges_m.size() != values.words.size()) {
            std::abort();
          }
        }
      }
    }
    Lms200ModeReply mode;
    DecodeModeReply(event.frame, &mode, &error);
    Lms200VariantReply variant;
    DecodeVariantReply(event.frame, &variant, &error);
    std::string type;
    DecodeTypeReply(event.frame, &type, &error);
    Lms200ConfigBlock block;
    DecodeConfigReply(event.frame, &block, &error);
    bool accepted = false;
    DecodeConfigWriteReply(event.frame, &accepted, &block, &error);
    Lms200DeviceStatus status;
    DecodeStatusReply(event.frame, &status, &error);
  }
  return 0;
}
