#include "operator_client/net/rejoin_policy.h"

#include <algorithm>
#include <string>

namespace mostar::client {

bool RejoinOptions::IsValid(std::string* error) const {
  if (first <= Duration::zero() || longest < first) {
    *error = "rejoin: need 0 < first <= longest";
    return false;
  }
  return true;
}

RejoinOptions RejoinOptionsAfter(double first_s) {
  RejoinOptions options;
  if (first_s > 0) options.first = FromSeconds(first_s);
  options.longest = std::max<Duration>(options.first, std::chrono::seconds(120));
  return options;
}

bool RejoinPolicy::Update(bool robot_seen, SteadyTime now) {
  if (robot_seen) {
    unseen_since_.reset();
    wait_ = options_.first;
    return false;
  }
  if (!unseen_since_) unseen_since_ = now;
  return now - *unseen_since_ >= wait_;
}

void RejoinPolicy::Rejoined(SteadyTime now) {
  unseen_since_ = now;
  wait_ = std::min(2 * wait_, options_.longest);
  ++rejoins_;
}

}  // namespace mostar::client
