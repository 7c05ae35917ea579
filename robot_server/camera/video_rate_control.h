// The H.264 target for everyone watching: one LinkRateController per viewer that sends receive
// reports (VideoFeedback), fed with the robot's record of the frames it wrote; the target is
// the lowest of the viewers heard from in the last `viewer_timeout`, never above the class
// target. Viewers behind the relay do not report (the relay forwards frames, not reports): the
// robot's uplink is judged by those that read it directly. At most `max_viewers` are tracked;
// a new one replaces the one heard from least recently. Thread-safe (the pipeline's compression
// thread and DDS threads).
#pragma once

#include <map>
#include <mutex>
#include <string>

#include "common/time/time.h"
#include "common/types/stereo_frame.h"
#include "robot_server/camera/link_rate_controller.h"

namespace mostar::camera {

struct VideoRateControlOptions {
  LinkRateOptions link;
  Duration viewer_timeout = std::chrono::seconds(2);
  size_t max_viewers = 16;
};

struct VideoRateStats {
  int viewers = 0;               // reporting within the timeout
  double target_bits_per_s = 0;  // 0: no viewer reports (the class target applies)
  double queue_ms = 0;           // the largest predicted queue among them
  uint64_t reports = 0;          // feedback messages taken
  uint64_t reports_refused = 0;  // malformed (AU numbers not increasing)
};

class VideoRateControl {
 public:
  explicit VideoRateControl(const VideoRateControlOptions& options = {});

  // The class target (0 = unlimited: the link options' max applies).
  void SetClassTarget(double bits_per_s);
  // A frame was written (compression thread).
  void OnFrameSent(uint64_t sequence, SteadyTime now, uint32_t bytes);
  // A viewer's report (DDS thread).
  void OnFeedback(const VideoFeedback& feedback, SteadyTime now);
  // The target for the next frame: the lowest viewer's, or `class_target` with no reports
  // (<= 0: unlimited, returned as 0).
  double Target(double class_target, SteadyTime now);
  // Skip the frame the encoder would write now (some viewer's queue is too long).
  bool ShouldSkipFrame(SteadyTime now);
  VideoRateStats Stats(SteadyTime now);

 private:
  struct Viewer {
    LinkRateController controller;
    SteadyTime last_report;
  };
  const VideoRateControlOptions options_;
  std::mutex mutex_;
  double class_target_ = 0;
  SentFrames sent_;
  std::map<std::string, Viewer> viewers_;
  uint64_t reports_ = 0;
  uint64_t refused_ = 0;
};

}  // namespace mostar::camera
