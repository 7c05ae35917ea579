// Two IEEE1394 (FireWire, IIDC) cameras through libdc1394 as one stereo camera, as on the
// MORDUC robot. Built only when libdc1394-2 is found (MOSTAR_HAVE_DC1394).
//
// Open() selects the cameras by GUID (0 = the first / second camera on the bus in enumeration
// order), sets operation mode, ISO speed, video mode, frame rate, exposure / shutter / gain,
// sets up `dma_buffers` DMA ring buffers each and starts transmission. Grab() waits for a
// frame of each camera (bus-cycle timestamps, microseconds since the epoch), always takes the
// newest frame in the ring (older ones are dropped and counted) and re-dequeues the older eye
// until both stamps are within `max_skew`. The pair's stamp is the midpoint.
// Without a FireWire bus or cameras, Open() fails with "no IEEE1394 camera found: ...".
// Not thread-safe (one capture thread).
#pragma once

#include <dc1394/dc1394.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/time/time.h"
#include "robot_server/camera/stereo_camera.h"

namespace mostar::camera {

class Dc1394StereoCamera final : public StereoCamera {
 public:
  struct Options {
    uint64_t left_guid = 0;   // 0 = first camera on the bus
    uint64_t right_guid = 0;  // 0 = second camera on the bus
    // IIDC format-0/1/2 mode "<width>x<height>_<coding>", coding YUV422 | RGB8 | MONO8.
    std::string video_mode = "640x480_YUV422";
    // MONO8 modes of colour sensors: "RGGB", "GRBG", "GBRG" or "BGGR"; empty = grey.
    std::string bayer_pattern;
    double frame_rate_hz = 30;  // IIDC rates: 1.875, 3.75, 7.5, 15, 30, 60, 120, 240
    int iso_speed_mbps = 400;   // 100, 200, 400, 800 (800 and up switch to 1394b mode)
    int dma_buffers = 4;        // ring buffers per camera, >= 2
    int exposure = -1;          // IIDC auto-exposure target, camera units; -1 = auto
    int shutter = -1;           // camera units; -1 = auto
    int gain = -1;              // camera units; -1 = auto
    Duration max_skew = std::chrono::milliseconds(5);
  };

  explicit Dc1394StereoCamera(const Options& options);
  ~Dc1394StereoCamera() override;

  bool Open(std::string* error) override;
  GrabResult Grab(Duration timeout, StereoImagePair* pair) override;
  void Close() override;
  bool IsOpen() const override { return open_; }
  StereoCameraInfo Info() const override;
  // ring_dropped_frames: older ring-buffer frames skipped and frames dropped while matching.
  std::vector<std::pair<std::string, uint64_t>> Counters() const override {
    return {{"ring_dropped_frames", dropped_frames_}};
  }
  uint64_t dropped_frames() const { return dropped_frames_; }

 private:
  bool Configure(dc1394camera_t* camera, const char* eye, bool* capturing, std::string* error);

  const Options options_;
  dc1394_t* context_ = nullptr;
  dc1394camera_t* left_ = nullptr;
  dc1394camera_t* right_ = nullptr;
  bool open_ = false;
  bool left_capturing_ = false;
  bool right_capturing_ = false;
  uint64_t left_guid_ = 0;
  uint64_t right_guid_ = 0;
  int width_px_ = 0;
  int height_px_ = 0;
  int coding_ = 0;  // internal: 0 YUV422 (UYVY), 1 RGB8, 2 MONO8
  uint64_t sequence_ = 0;
  uint64_t dropped_frames_ = 0;
};

}  // namespace mostar::camera
