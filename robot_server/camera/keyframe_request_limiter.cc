#include "robot_server/camera/keyframe_request_limiter.h"

namespace mostar::camera {

void KeyframeRequestLimiter::Request(SteadyTime now) {
  ++counters_.requests;
  if (last_idr_ && now - *last_idr_ < min_interval_) ++counters_.deferred;
  pending_ = true;
}

bool KeyframeRequestLimiter::ShouldSendIdr(SteadyTime now) {
  if (!pending_) return false;
  if (last_idr_ && now - *last_idr_ < min_interval_) return false;
  ++counters_.answered;
  return true;
}

void KeyframeRequestLimiter::OnIdrSent(SteadyTime now) {
  pending_ = false;
  last_idr_ = now;
}

}  // namespace mostar::camera
