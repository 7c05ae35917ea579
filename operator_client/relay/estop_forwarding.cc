#include "operator_client/relay/estop_forwarding.h"

namespace mostar::relay {

std::optional<EmergencyStop> EstopForwarding::OnObserverEstop(const EmergencyStop& received,
                                                              Time now, SteadyTime steady_now) {
  ++stats_.received;
  if (!received.engage) {
    ++stats_.releases_refused;
    return std::nullopt;
  }
  if (last_forwarded_ && steady_now - *last_forwarded_ < min_interval_) {
    ++stats_.rate_limited;
    return std::nullopt;
  }
  last_forwarded_ = steady_now;
  ++stats_.forwarded;
  EmergencyStop out;
  out.stamp = now;
  out.sender_id = relay_id_;
  out.engage = true;
  return out;
}

}  // namespace mostar::relay
