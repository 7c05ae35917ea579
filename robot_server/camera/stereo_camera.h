// The stereo camera device interface: one call to Grab() yields both eyes of one capture.
//
// Implementations: Dc1394StereoCamera (two IEEE1394 cameras), V4l2StereoCamera (two webcams via
// OpenCV), FileStereoCamera (videos or image sequences, for offline work), FakeStereoCamera
// (scripted, for unit tests); the simulator provides another.
//
// Threading: an instance is not thread-safe. One thread (the capture thread of CameraPipeline)
// calls Open, Grab and Close; Info() may be called from that thread only as well.
// Images: BGR8 (CV_8UC3), OpenCV camera frame (x right, y down, origin top-left pixel centre).
#pragma once

#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/time/time.h"

namespace mostar::camera {

// Both eyes of one capture. Left and right have the same size.
struct StereoImagePair {
  uint64_t sequence = 0;  // pair counter of the camera, +1 per delivered pair (gaps = drops)
  Time stamp;             // capture time of the pair (wall clock, UTC)
  cv::Mat left;           // CV_8UC3 BGR
  cv::Mat right;          // CV_8UC3 BGR
};

enum class GrabStatus {
  kOk = 0,
  kTimeout,      // no pair within the timeout; the device may still be there
  kDeviceLost,   // the device is gone (unplugged, I/O error): Close() and Open() again later
  kEndOfStream,  // a finite source (files) has no more pairs
  kNotOpen,      // Grab() without a successful Open()
};
const char* GrabStatusName(GrabStatus status);

struct GrabResult {
  GrabStatus status = GrabStatus::kOk;
  std::string message;  // empty when kOk; otherwise what happened, for logs and health
  bool ok() const { return status == GrabStatus::kOk; }
  static GrabResult Ok() { return {}; }
  static GrabResult Error(GrabStatus status, std::string message) {
    return {status, std::move(message)};
  }
};

struct StereoCameraInfo {
  std::string backend;      // "dc1394", "v4l2", "file", "fake", "sim"
  std::string left_device;  // device path, GUID or file of the left eye
  std::string right_device;
  int width_px = 0;  // size of each eye's image as delivered by Grab()
  int height_px = 0;
  double frame_rate_hz = 0;  // nominal pair rate; 0 = unknown or unpaced
};

class StereoCamera {
 public:
  StereoCamera() = default;
  virtual ~StereoCamera() = default;
  StereoCamera(const StereoCamera&) = delete;
  StereoCamera& operator=(const StereoCamera&) = delete;

  // Opens and starts both devices. False with a message in `error` (never null) when a device
  // is missing or refuses the configuration; safe to call again later. Opening an open camera
  // closes it first.
  virtual bool Open(std::string* error) = 0;
  // Waits at most `timeout` for the next pair and writes it to `pair` (never null). The
  // images may share memory with the camera's buffers only until the next Grab().
  virtual GrabResult Grab(Duration timeout, StereoImagePair* pair) = 0;
  // Stops both devices and releases them. Idempotent.
  virtual void Close() = 0;
  virtual bool IsOpen() const = 0;
  // Resolution, rate and device names; valid after a successful Open() (configured values
  // before).
  virtual StereoCameraInfo Info() const = 0;
  // Backend-specific counters for the health report (e.g. frames dropped while pairing, skew
  // between the eyes in microseconds), appended to CameraPipeline's counters. Default: none.
  virtual std::vector<std::pair<std::string, uint64_t>> Counters() const { return {}; }
};

}  // namespace mostar::camera
