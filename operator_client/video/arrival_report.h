// A viewer's record of the H.264 frames that reached it, cut into receive reports for the
// robot's rate control (VideoFeedback, robot_server/camera/video_rate_control.h): a report is
// due every `period` while frames arrive, or at once when VideoFeedback::kMaxArrivals are
// pending. Arrival times are the viewer's monotonic clock; only their differences count.
// Used by the console (StereoReceiver) and by mostar_relay, which reports the robot's uplink.
// Not thread-safe: callers hold their own lock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/time/time.h"
#include "common/types/stereo_frame.h"

namespace mostar::client {

class ArrivalReport {
 public:
  static constexpr Duration kDefaultPeriod = std::chrono::milliseconds(50);
  explicit ArrivalReport(Duration period = kDefaultPeriod) : period_(period) {}

  // Frame `sequence` (its AU number) of `bytes` (both eyes) arrived at `arrival`. Not recorded
  // (counted in not_recorded()) when it is not newer than the last one recorded, or when
  // 4 * kMaxArrivals are pending (nobody takes the reports).
  void Add(uint64_t sequence, SteadyTime arrival, size_t bytes);
  // The arrivals to report at `now`, oldest first, at most kMaxArrivals; empty when none is due.
  std::vector<VideoFrameArrival> TakeDue(SteadyTime now);

  size_t pending() const { return pending_.size(); }
  uint64_t not_recorded() const { return not_recorded_; }

 private:
  const Duration period_;
  std::vector<VideoFrameArrival> pending_;
  std::optional<uint64_t> last_sequence_;
  std::optional<SteadyTime> last_report_;
  uint64_t not_recorded_ = 0;
};

}  // namespace mostar::client
