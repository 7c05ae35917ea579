// Camera images. `CompressedImage` is one eye as it travels (JPEG bytes); `StereoPair` is both
// eyes of one capture, which carry the same stamp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "common/types/eye.h"

namespace mostar {

struct CompressedImage {
  Time stamp;            // capture time (both eyes of a pair share it)
  std::string frame_id;  // "camera_left" or "camera_right"
  std::string format;    // "jpeg"
  std::vector<uint8_t> data;
};

// Intrinsics of one eye in pixels of the published images (OpenCV conventions).
struct CameraIntrinsicsInfo {
  Time stamp;
  std::string frame_id;  // "camera_left" or "camera_right"
  int width_px = 0;
  int height_px = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;  // k1 k2 p1 p2 [k3]
};

struct CompressedStereoPair {
  uint64_t sequence = 0;  // pair counter of the producer
  Time encoded;           // when both JPEGs were done (wall clock of the producer)
  CompressedImage left;
  CompressedImage right;
};

// The robot-side stages of one pair (robot clock), published on rt/mostar/camera/timing.
struct FrameTiming {
  Time capture;
  Time encoded;
  Time written;
};

}  // namespace mostar
