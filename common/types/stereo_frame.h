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
  Time encoded;           // when both eyes were compressed (wall clock of the producer)
  CompressedImage left;
  CompressedImage right;
};

// Both eyes of one capture as H.264 access units (Annex B) of two streams, one per eye, that
// advance together (idl/mostar_msgs.idl StereoVideoFrame_).
struct StereoVideoFrame {
  uint64_t sequence = 0;  // AU number of both streams: consecutive for consecutive AUs
  Time stamp;             // capture time of both eyes
  Time encoded;           // both AUs done (producer's wall clock)
  bool idr = false;       // both AUs are IDRs with SPS and PPS: decoding may start here
  int width_px = 0;       // of each eye's pictures
  int height_px = 0;
  std::string format = "h264";
  std::vector<uint8_t> left;
  std::vector<uint8_t> right;
};

// A viewer asks the robot for an IDR (it joined, lost an AU, or could not decode one).
struct KeyframeRequest {
  Time stamp;              // sender's clock
  std::string sender_id;   // a claim (logs only)
  uint64_t last_sequence;  // last AU decoded, 0 = none
  std::string reason;      // "join", "gap", "error"
};

// When a viewer received one StereoVideoFrame.
struct VideoFrameArrival {
  uint64_t sequence = 0;   // the frame's AU number
  int64_t arrival_ns = 0;  // viewer's monotonic clock (only differences count)
  uint32_t bytes = 0;      // both eyes
};

// A viewer's receive report for the robot's rate control.
struct VideoFeedback {
  Time stamp;                               // sender's clock
  std::string sender_id;                    // a claim
  std::vector<VideoFrameArrival> arrivals;  // increasing AU numbers, at most kMaxArrivals
  static constexpr size_t kMaxArrivals = 64;
};

// The robot-side stages of one pair (robot clock), published on rt/mostar/camera/timing.
struct FrameTiming {
  Time capture;
  Time encoded;
  Time written;
};

}  // namespace mostar
