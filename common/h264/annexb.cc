#include "common/h264/annexb.h"

#include <algorithm>

namespace mostar::h264 {

std::vector<uint8_t> NalTypes(const uint8_t* data, size_t size) {
  std::vector<uint8_t> types;
  size_t i = 0;
  while (i + 3 <= size) {
    if (data[i] == 0 && data[i + 1] == 0 && data[i + 2] == 1) {
      if (i + 3 < size) types.push_back(data[i + 3] & 0x1f);
      i += 3;
    } else {
      ++i;
    }
  }
  return types;
}

bool IsSelfContainedIdr(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> types = NalTypes(data, size);
  const auto has = [&types](uint8_t t) {
    return std::find(types.begin(), types.end(), t) != types.end();
  };
  return has(kNalIdr) && has(kNalSps) && has(kNalPps);
}

}  // namespace mostar::h264
