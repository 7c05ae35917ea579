// Stereo pairs from files, for offline work and tests: two videos, two image sequences
// (sorted glob patterns, e.g. "left/*.png"), or one side-by-side video (left half = left eye).
//
// Pacing: `paced` delivers at `frame_rate_hz` in real time (like a camera); otherwise as fast
// as Grab() is called. Stamps come from the injected clock at delivery. At the end: kEndOfStream,
// or the first pair again with `loop`. Grey images are converted to BGR. A left/right count
// or size mismatch is refused at Open(); an unreadable image is a kDeviceLost grab error.
// Not thread-safe (one capture thread), as every StereoCamera.
#pragma once

#include <memory>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "robot_server/camera/stereo_camera.h"

namespace mostar::camera {

class FileStereoCamera final : public StereoCamera {
 public:
  enum class Source { kTwoVideos, kTwoImageSequences, kSideBySideVideo };
  struct Options {
    Source source = Source::kTwoImageSequences;
    std::string left;   // video path or glob pattern; the side-by-side video for kSideBySideVideo
    std::string right;  // unused for kSideBySideVideo
    double frame_rate_hz = 30;  // pacing, and Info() for image sequences; > 0
    bool paced = false;
    bool loop = false;
    const Clock* clock = &SystemClock::Instance();  // not owned
  };

  explicit FileStereoCamera(const Options& options);
  ~FileStereoCamera() override;

  bool Open(std::string* error) override;
  GrabResult Grab(Duration timeout, StereoImagePair* pair) override;
  void Close() override;
  bool IsOpen() const override { return open_; }
  StereoCameraInfo Info() const override;

 private:
  bool ReadNext(cv::Mat* left, cv::Mat* right, std::string* error, bool* end);
  bool Rewind(std::string* error);

  const Options options_;
  bool open_ = false;
  std::vector<std::string> left_files_;
  std::vector<std::string> right_files_;
  size_t next_index_ = 0;
  cv::VideoCapture left_video_;
  cv::VideoCapture right_video_;
  uint64_t sequence_ = 0;
  int width_px_ = 0;
  int height_px_ = 0;
  SteadyTime next_due_;
};

}  // namespace mostar::camera
