// H.264 Annex B byte streams: the NAL units of one access unit (AU), as libx264 writes them and
// foxglove_msgs/CompressedVideo carries them (start codes 00 00 01 or 00 00 00 01).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mostar::h264 {

// NAL unit types (ITU-T H.264 table 7-1) that the codec's users look at.
enum NalType : uint8_t {
  kNalSlice = 1,  // a non-IDR picture's slice
  kNalIdr = 5,    // an IDR picture's slice: decoding can start here
  kNalSei = 6,
  kNalSps = 7,
  kNalPps = 8,
  kNalAud = 9,
};

// The nal_unit_type of every NAL unit in `data`, in order; empty when `data` holds no start
// code. Bytes before the first start code are ignored.
std::vector<uint8_t> NalTypes(const uint8_t* data, size_t size);
inline std::vector<uint8_t> NalTypes(const std::vector<uint8_t>& data) {
  return NalTypes(data.data(), data.size());
}

// The AU holds an IDR slice together with the SPS and PPS it needs: a decoder may start on it.
bool IsSelfContainedIdr(const uint8_t* data, size_t size);
inline bool IsSelfContainedIdr(const std::vector<uint8_t>& data) {
  return IsSelfContainedIdr(data.data(), data.size());
}

}  // namespace mostar::h264
