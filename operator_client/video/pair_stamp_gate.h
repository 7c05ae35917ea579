// Which completed stereo pairs may be shown, judged by their capture stamp (robot clock), so
// that pairs are shown in capture order and one wrong stamp cannot freeze the video:
// - kFuture: with the clock offset known, a stamp later than the robot's time now (this
//   machine's time plus the offset) by more than future_tolerance plus the offset's
//   uncertainty. Refused: shown, it would make every later pair look late.
// - kLate: not newer than the newest pair shown (several pairs in flight can complete out of
//   order). Refused.
// - kResync: shown although not newer, because the newest pair shown is itself from the future
//   by the offset now known (it came before the offset was), or because only late pairs came for
//   resync_after and at least kResyncLatePairs of them (the robot's clock stepped back). Both
//   restart the order from this pair.
// - kShow: newer than every pair shown.
// Pure: the caller passes the times. Not thread-safe.
#pragma once

#include <cstdint>
#include <optional>

#include "common/time/time.h"
#include "common/timesync/clock_offset_estimator.h"

namespace mostar::client {

struct PairStampGateOptions {
  Duration future_tolerance = std::chrono::milliseconds(500);  // >= 0, plus the uncertainty
  Duration resync_after = std::chrono::seconds(2);             // > 0
};

enum class PairVerdict { kShow, kResync, kFuture, kLate };

struct PairStampGateStats {
  uint64_t future = 0;
  uint64_t late = 0;
  uint64_t resyncs = 0;
};

class PairStampGate {
 public:
  static constexpr int kResyncLatePairs = 3;

  explicit PairStampGate(const PairStampGateOptions& options = {}) : options_(options) {}

  // The robot's clock minus this machine's (the console's ping estimate); ignored until known.
  void SetClockOffset(const timesync::ClockOffsetEstimate& robot_minus_local);
  // A pair stamped `stamp` completed at `now` (wall clock) / `now_steady` (this machine).
  PairVerdict Check(Time stamp, Time now, SteadyTime now_steady);

  const PairStampGateStats& stats() const { return stats_; }

 private:
  const PairStampGateOptions options_;
  timesync::ClockOffsetEstimate offset_;
  std::optional<Time> newest_;  // stamp of the newest pair shown
  SteadyTime last_shown_;
  int late_streak_ = 0;
  PairStampGateStats stats_;
};

}  // namespace mostar::client
