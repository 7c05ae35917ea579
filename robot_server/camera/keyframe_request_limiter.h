// Decides when the robot's H.264 encoder sends an IDR for viewers that asked for one (they
// joined, lost an access unit, or could not decode one).
//
// As libwebrtc does (kMinKeyframeSendIntervalMs), IDRs on request are at least `min_interval`
// apart, so that many viewers losing data at once, or one viewer asking in a loop, cost at most
// one IDR per interval. Unlike libwebrtc, a request that arrives inside the interval is not
// ignored but deferred to its end: every request is answered within min_interval. An IDR the
// encoder sends for another reason (the first frame, a restart) counts as the answer.
// Not thread-safe: the caller serialises (the camera pipeline's lock).
#pragma once

#include <cstdint>
#include <optional>

#include "common/time/time.h"

namespace mostar::camera {

struct KeyframeRequestCounters {
  uint64_t requests = 0;  // Request() calls
  uint64_t answered = 0;  // IDRs sent because of a request (ShouldSendIdr true)
  uint64_t deferred = 0;  // requests that arrived inside the interval
};

class KeyframeRequestLimiter {
 public:
  explicit KeyframeRequestLimiter(Duration min_interval = std::chrono::milliseconds(300))
      : min_interval_(min_interval) {}

  // A viewer asked for an IDR at `now`.
  void Request(SteadyTime now);
  // Whether the next frame, encoded at `now`, must be an IDR for a pending request. True at
  // most once per min_interval; the caller then encodes an IDR and calls OnIdrSent.
  bool ShouldSendIdr(SteadyTime now);
  // An IDR went out at `now` (for a request or any other reason): pending requests are answered.
  void OnIdrSent(SteadyTime now);

  bool pending() const { return pending_; }
  const KeyframeRequestCounters& counters() const { return counters_; }

 private:
  const Duration min_interval_;
  bool pending_ = false;
  std::optional<SteadyTime> last_idr_;
  KeyframeRequestCounters counters_;
};

}  // namespace mostar::camera
