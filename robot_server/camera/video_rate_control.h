// The H.264 target for everyone watching: one LinkRateController per viewer that sends receive
// reports (VideoFeedback), fed with the robot's record of the frames it wrote; the target is
// the lowest of the viewers heard from in the last `viewer_timeout`, never above the class
// target, and a smaller fraction of it while nobody reports. Viewers behind mostar_relay do not
// report to the robot: the relay reports its own arrivals, which judge the robot's uplink. At most
// `max_viewers` are tracked; a new one replaces the one heard from least recently. Thread-safe (the
// pipeline's compression thread and DDS threads).
#pragma once

#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "common/time/time.h"
#include "common/types/stereo_frame.h"
#include "robot_server/camera/link_rate_controller.h"

namespace mostar::camera {

struct VideoRateControlOptions {
  LinkRateOptions link;
  Duration viewer_timeout = std::chrono::seconds(2);
  size_t max_viewers = 16;
  // Skipping frames stops for one frame after this long: only frames sent measure the link, and
  // a queue estimate left over from an outage (frames that waited it out) would otherwise keep
  // the encoder silent until it aged away.
  Duration max_skip = std::chrono::milliseconds(500);
  // Of the class target while no viewer reports (start, or every viewer quiet after an
  // outage): below where a viewer's controller starts (link.start_fraction), because each
  // viewer behind the relay gets a copy and viewers behind one NAT share its downlink (at half
  // of an 8 Mbit/s class, two copies filled an 8 Mbit/s downlink after a robot_server restart
  // until the first reports came: docs/networking.md).
  double unreported_fraction = 0.25;
  // A viewer silent for longer than viewer_timeout but less than this (its link lost so much
  // that no frame got through, or an outage) still caps that fallback at its own target, which
  // the silence rule keeps lowering (LinkRateController::OnSilence): the quarter of the class
  // would otherwise be written into the link that just starved it.
  Duration silent_cap = std::chrono::seconds(10);
  // The video writers' repair deadline (dds.video_repair_deadline_ms; 0: none), for
  // RepairDeadlineWarning.
  Duration repair_deadline{0};
  // dds.video_repair_deadline_auto: the deadline follows the viewers' links
  // (RepairDeadlineUpdate): link.repair_hold + 1.5 x the largest report lag (a round trip) +
  // auto_deadline_margin, within [link.repair_hold + auto_deadline_margin, max_repair_deadline];
  // changed when it is off by more than auto_deadline_change, at most every
  // auto_deadline_interval (each change is announced to every participant).
  bool auto_repair_deadline = false;
  Duration auto_deadline_margin = std::chrono::milliseconds(50);
  Duration max_repair_deadline = std::chrono::seconds(2);
  double auto_deadline_change = 0.2;
  Duration auto_deadline_interval = std::chrono::seconds(5);
};

struct VideoRateStats {
  int viewers = 0;                // reporting within the timeout
  double target_bits_per_s = 0;   // 0: no viewer reports (the class target applies)
  double queue_ms = 0;            // the largest predicted queue among them
  double report_lag_ms = 0;       // the largest least report lag among them (about a round trip)
  double repair_deadline_ms = 0;  // set by RepairDeadlineUpdate (0: none yet)
  uint64_t reports = 0;           // feedback messages taken
  uint64_t reports_refused = 0;   // malformed (AU numbers not increasing)
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
  // The target for the next frame: the lowest viewer's (each first lowered by its silence, if
  // any); with no viewer heard from within the timeout, `class_target` times
  // unreported_fraction (<= 0: unlimited, returned as 0), at most the lowest target of the
  // viewers heard from within silent_cap.
  double Target(double class_target, SteadyTime now);
  // Skip the frame the encoder would write now (some viewer's queue is too long), but never for
  // longer than max_skip in a row.
  bool ShouldSkipFrame(SteadyTime now);
  VideoRateStats Stats(SteadyTime now);
  // One line per viewer heard from within the timeout, for the log: id, target, throughput,
  // queue, usage, decreases, frames held back by repairs.
  std::string Describe(SteadyTime now);
  // Empty, or why the repair deadline is too short for some reporting viewer's link: a repair
  // takes the repair period (options.link.repair_hold) and a round trip (its report lag), and a
  // deadline below that gives up lost fragments instead of repairing them.
  std::string RepairDeadlineWarning(SteadyTime now);
  // With auto_repair_deadline: the deadline the video writers should now have, when it should
  // change (see the options); nullopt otherwise (also before any viewer's lag is measured).
  std::optional<Duration> RepairDeadlineUpdate(SteadyTime now);

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
  std::optional<SteadyTime> skipping_since_;
  Duration auto_deadline_{0};  // 0: none set yet
  std::optional<SteadyTime> auto_deadline_set_;
};

}  // namespace mostar::camera
