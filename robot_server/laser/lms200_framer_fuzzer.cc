// libFuzzer target: arbitrary bytes through the framer and every decoder must never crash,
// hang or read out of bounds; every frame reported must appear in the input with a valid CRC
// (the CRC bytes of the input, not recomputed ones), and every input byte must be accounted
// for (a frame, an ACK, a NAK or a discarded byte).
#include <algorithm>
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
  // The framer consumes the stream in order: every byte ends up in exactly one frame, ACK or
  // NAK event, or is discarded.
  const uint8_t* stream = data + 1;
  const size_t stream_size = size - 1;
  const FramerStats& stats = framer.stats();
  size_t event_bytes = stats.acks + stats.naks;
  for (const FramerEvent& event : events) {
    if (event.type == FramerEventType::kFrame) event_bytes += event.frame.wire_bytes();
  }
  if (event_bytes + stats.bytes_discarded != stream_size) std::abort();
  std::string error;
  size_t cursor = 0;  // frames are reported in stream order and never overlap
  for (const FramerEvent& event : events) {
    if (event.type != FramerEventType::kFrame) continue;
    // The frame must be in the input, at or after the end of the previous frame, with the CRC
    // the input carries there matching Lms200Crc over the input's header and payload. Copies
    // of the same header and payload with a wrong CRC are skipped: the framer rejects those.
    const size_t length = event.frame.payload.size();
    const size_t frame_bytes = event.frame.wire_bytes();
    const uint8_t header[4] = {kLms200Stx, event.frame.address, static_cast<uint8_t>(length & 0xFF),
                               static_cast<uint8_t>(length >> 8)};
    bool found = false;
    for (size_t offset = cursor; !found && offset + frame_bytes <= stream_size; ++offset) {
      const uint8_t* wire = stream + offset;
      if (!std::equal(header, header + 4, wire) ||
          !std::equal(event.frame.payload.begin(), event.frame.payload.end(), wire + 4)) {
        continue;
      }
      const uint16_t input_crc = static_cast<uint16_t>(wire[length + 4] | (wire[length + 5] << 8));
      if (Lms200Crc(wire, length + 4) != input_crc) continue;
      found = true;
      cursor = offset + frame_bytes;
    }
    if (!found) std::abort();
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
