// Camera images. `CompressedImage` is one eye as it travels (JPEG bytes); `StereoPair` is both
// eyes of one capture, which carry the same stamp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/time/time.h"

namespace mostar {

enum class Eye { kLeft = 0, kRight = 1 };

inline const char* EyeName(Eye eye) { return eye == Eye::kLeft ? "left" : "right"; }

struct CompressedImage {
  Time stamp;            // capture time (both eyes of a pair share it)
  std::string frame_id;  // "camera_left" or "camera_right"
  std::string format;    // "jpeg"
  std::vector<uint8_t> data;
};

struct CompressedStereoPair {
  uint64_t sequence = 0;  // pair counter of the producer
  CompressedImage left;
  CompressedImage right;
};

}  // namespace mostar
