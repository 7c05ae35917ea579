#include "operator_client/ui/lease_client.h"

#include <utility>

namespace mostar::ui {

LeaseClient::LeaseClient(std::string client_id, bool pilot)
    : client_id_(std::move(client_id)), pilot_(pilot), want_control_(pilot) {}

ControlRequest LeaseClient::Update(const std::optional<ControlLease>& lease, SteadyTime now) {
  const bool holding = lease && lease->holder_id == client_id_;
  if (!holding) {
    holding_since_.reset();
  } else if (!holding_since_) {
    holding_since_ = now;
  }
  if (!want_control_ || holding || (next_request_ && now < *next_request_)) {
    return ControlRequest::kNone;
  }
  next_request_ = now + kRequestPeriod;
  return ControlRequest::kTake;
}

void LeaseClient::Take() {
  if (!pilot_) return;
  want_control_ = true;
  next_request_.reset();
}

ControlRequest LeaseClient::Release() {
  want_control_ = false;
  return ControlRequest::kRelease;
}

}  // namespace mostar::ui
