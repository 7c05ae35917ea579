#include "common/udp_over_tcp/dial_plan.h"

#include <algorithm>

namespace mostar::udp_over_tcp {

DialPlan::DialPlan(DialPlanOptions options)
    : options_(options), backoff_(options.initial_backoff) {}

bool DialPlan::ShouldDial(Clock::time_point now, int in_flight) const {
  return in_flight < options_.max_in_flight && now >= next_dial_;
}

void DialPlan::Started(Clock::time_point now) {
  next_dial_ = std::max(next_dial_, now + options_.interval);
}

std::chrono::milliseconds DialPlan::Answered(Clock::time_point now) {
  const std::chrono::milliseconds wait = backoff_;
  next_dial_ = std::max(next_dial_, now + wait);
  backoff_ = std::min(backoff_ * 2, options_.max_backoff);
  return wait;
}

void DialPlan::Connected() { backoff_ = options_.initial_backoff; }

}  // namespace mostar::udp_over_tcp
