// Two V4L2 webcams (through OpenCV's VideoCapture, V4L2 backend) as one stereo camera.
//
// Each device is read by its own thread, which stamps a frame with the clock when the driver
// hands it over (grab), before decoding (retrieve). A StereoPairer matches left and right by
// nearest stamp within `max_skew`; frames without a partner are dropped and counted, and the
// skew drift between the two free-running cameras is measured (pairer_stats()). A device
// that fails `max_read_failures` reads in a row is reported lost (kDeviceLost).
// StereoCamera methods: one capture thread. pairer_stats(): any thread.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <opencv2/videoio.hpp>
#include <string>
#include <thread>

#include "common/time/time.h"
#include "robot_server/camera/stereo_camera.h"
#include "robot_server/camera/stereo_pairer.h"

namespace mostar::camera {

class V4l2StereoCamera final : public StereoCamera {
 public:
  struct Options {
    std::string left_device = "/dev/video0";  // path (udev symlinks work) or a number
    std::string right_device = "/dev/video2";
    int width_px = 640;
    int height_px = 480;
    double frame_rate_hz = 30;
    std::string fourcc = "MJPG";  // "MJPG" (two webcams on one USB bus need it) or "YUYV"
    int exposure = -1;            // driver units; -1 = automatic
    int gain = -1;                // driver units; -1 = driver default
    StereoPairerOptions pairing;  // max_skew ~ a third of the frame period
    int max_read_failures = 10;
    const Clock* clock = &SystemClock::Instance();  // not owned
  };

  explicit V4l2StereoCamera(const Options& options);
  ~V4l2StereoCamera() override;

  bool Open(std::string* error) override;
  GrabResult Grab(Duration timeout, StereoImagePair* pair) override;
  void Close() override;
  bool IsOpen() const override;
  StereoCameraInfo Info() const override;
  // pair_dropped_left / _right (unpaired frames), pair_skew_us_abs (|mean left - right|),
  // pair_drift_us_per_s_abs (how fast the two free-running cameras slide apart).
  std::vector<std::pair<std::string, uint64_t>> Counters() const override;
  StereoPairerStats pairer_stats() const;

 private:
  void ReadLoop(bool left);
  bool OpenDevice(const std::string& device, cv::VideoCapture* capture, std::string* error);

  const Options options_;
  cv::VideoCapture left_;
  cv::VideoCapture right_;
  std::thread left_thread_;
  std::thread right_thread_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  StereoPairer pairer_;
  bool open_ = false;
  bool stop_ = false;
  std::string lost_message_;  // non-empty once a device is lost
  uint64_t sequence_ = 0;
  int width_px_ = 0;
  int height_px_ = 0;
  double frame_rate_hz_ = 0;
};

}  // namespace mostar::camera
