#include "operator_client/video/pair_stamp_gate.h"

namespace mostar::client {

void PairStampGate::SetClockOffset(const timesync::ClockOffsetEstimate& robot_minus_local) {
  if (robot_minus_local.known) offset_ = robot_minus_local;
}

PairVerdict PairStampGate::Check(Time stamp, Time now, SteadyTime now_steady) {
  bool resync = false;
  if (offset_.known) {
    const Time latest_possible =
        offset_.ToResponderTime(now) + options_.future_tolerance + offset_.uncertainty;
    if (stamp > latest_possible) {
      ++stats_.future;
      return PairVerdict::kFuture;
    }
    if (newest_ && *newest_ > latest_possible) {
      newest_.reset();  // shown before the offset was known; it was from the future
      resync = true;
    }
  }
  if (newest_ && stamp <= *newest_) {
    ++late_streak_;
    if (late_streak_ < kResyncLatePairs || now_steady - last_shown_ < options_.resync_after) {
      ++stats_.late;
      return PairVerdict::kLate;
    }
    resync = true;
  }
  newest_ = stamp;
  last_shown_ = now_steady;
  late_streak_ = 0;
  if (resync) ++stats_.resyncs;
  return resync ? PairVerdict::kResync : PairVerdict::kShow;
}

}  // namespace mostar::client
