#include "robot_server/drive/pilot_lease.h"

#include <utility>

#include "common/check/check.h"

namespace mostar::drive {

const char* RoleName(Role role) {
  switch (role) {
    case Role::kObserver:
      return "observer";
    case Role::kPilot:
      return "pilot";
  }
  return "unknown";
}

const char* LeaseDecisionName(LeaseDecision decision) {
  switch (decision) {
    case LeaseDecision::kGranted:
      return "granted";
    case LeaseDecision::kReleased:
      return "released";
    case LeaseDecision::kRefusedObserver:
      return "refused: observer";
    case LeaseDecision::kRefusedHeld:
      return "refused: held by an equal or stronger pilot";
    case LeaseDecision::kRefusedNotHolder:
      return "refused: not the holder";
  }
  return "unknown";
}

RoleEntry RoleTable::Lookup(const std::string& client_id) const {
  const auto it = entries_.find(client_id);
  return it == entries_.end() ? RoleEntry{} : it->second;
}

PilotLease::PilotLease(const Clock& clock, RoleTable roles, Duration holder_timeout)
    : clock_(clock), roles_(std::move(roles)), holder_timeout_(holder_timeout) {
  MOSTAR_CHECK(holder_timeout_ > Duration::zero()) << "holder_timeout must be positive";
  lease_.since = clock_.Now();
}

void PilotLease::ChangeHolderLocked(const std::string& holder_id, int32_t strength) {
  lease_.holder_id = holder_id;
  lease_.holder_strength = strength;
  lease_.since = clock_.Now();
  ++lease_.lease_sequence;
  holder_heard_ = clock_.SteadyNow();
}

LeaseDecision PilotLease::HandleRequest(const ControlRequest& request) {
  const RoleEntry role = roles_.Lookup(request.sender_id);
  std::lock_guard<std::mutex> lock(mutex_);
  if (!request.take) {
    if (lease_.holder_id.empty() || lease_.holder_id != request.sender_id) {
      ++stats_.refused;
      return LeaseDecision::kRefusedNotHolder;
    }
    ChangeHolderLocked("", 0);
    ++stats_.released;
    return LeaseDecision::kReleased;
  }
  if (role.role != Role::kPilot) {
    ++stats_.refused;
    return LeaseDecision::kRefusedObserver;
  }
  if (lease_.holder_id == request.sender_id) {
    holder_heard_ = clock_.SteadyNow();
    return LeaseDecision::kGranted;
  }
  if (lease_.holder_id.empty()) {
    ChangeHolderLocked(request.sender_id, role.strength);
    ++stats_.granted;
    return LeaseDecision::kGranted;
  }
  if (role.strength > lease_.holder_strength) {
    ChangeHolderLocked(request.sender_id, role.strength);
    ++stats_.granted;
    ++stats_.takeovers;
    return LeaseDecision::kGranted;
  }
  ++stats_.refused;
  return LeaseDecision::kRefusedHeld;
}

bool PilotLease::OnLivelinessLost(const std::string& client_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (client_id.empty() || lease_.holder_id != client_id) return false;
  ChangeHolderLocked("", 0);
  ++stats_.holder_lost;
  return true;
}

void PilotLease::NoteAlive(const std::string& client_id) {
  const SteadyTime now = clock_.SteadyNow();
  std::lock_guard<std::mutex> lock(mutex_);
  if (!client_id.empty() && lease_.holder_id == client_id) holder_heard_ = now;
}

std::optional<std::string> PilotLease::ExpireSilentHolder(SteadyTime now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (lease_.holder_id.empty() || now - holder_heard_ <= holder_timeout_) return std::nullopt;
  std::string lost = lease_.holder_id;
  ChangeHolderLocked("", 0);
  ++stats_.holder_lost;
  return lost;
}

ControlLease PilotLease::lease() const {
  std::lock_guard<std::mutex> lock(mutex_);
  ControlLease out = lease_;
  out.stamp = clock_.Now();
  return out;
}

std::string PilotLease::holder() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lease_.holder_id;
}

bool PilotLease::IsHolder(const std::string& client_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !client_id.empty() && lease_.holder_id == client_id;
}

bool PilotLease::MayEngageEstop(const std::string& client_id) const {
  return roles_.Known(client_id);
}

bool PilotLease::MayReleaseEstop(const std::string& client_id) const {
  return roles_.Lookup(client_id).role == Role::kPilot && IsHolder(client_id);
}

Role PilotLease::RoleOf(const std::string& client_id) const {
  return roles_.Lookup(client_id).role;
}

PilotLeaseStats PilotLease::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

}  // namespace mostar::drive
