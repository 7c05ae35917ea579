#include "robot_server/node/sender_check.h"

#include <utility>

#include "common/identity/client_id.h"

namespace mostar::server {

const char* SenderChannelName(SenderChannel channel) {
  switch (channel) {
    case SenderChannel::kCommand:
      return "cmd_vel";
    case SenderChannel::kEmergencyStop:
      return "estop";
    case SenderChannel::kControlRequest:
      return "control_request";
    case SenderChannel::kClockPing:
      return "clock_ping";
  }
  return "?";
}

const char* SenderVerdictName(SenderVerdict verdict) {
  switch (verdict) {
    case SenderVerdict::kVerified:
      return "verified";
    case SenderVerdict::kUnverified:
      return "unverified (no DDS Security)";
    case SenderVerdict::kMismatch:
      return "sender_id is not the client whose partition it came in";
    case SenderVerdict::kInvalidId:
      return "invalid sender_id";
  }
  return "?";
}

SenderVerdict SenderCheck::Check(SenderChannel channel, const std::string& sender_id,
                                 const std::string& partition_client) {
  SenderVerdict verdict;
  if (!identity::IsValidClientId(sender_id)) {
    verdict = SenderVerdict::kInvalidId;
    ++invalid_;
  } else if (sender_id != partition_client) {
    verdict = SenderVerdict::kMismatch;
    ++mismatch_;
  } else {
    verdict = identities_verified_ ? SenderVerdict::kVerified : SenderVerdict::kUnverified;
  }
  if (!Admits(verdict)) ++dropped_by_channel_[static_cast<size_t>(channel)];
  return verdict;
}

uint64_t SenderCheck::dropped() const { return mismatch_ + invalid_; }

std::vector<std::pair<std::string, uint64_t>> SenderCheck::HealthCounters() const {
  std::vector<std::pair<std::string, uint64_t>> out = {
      {"identities_verified", identities_verified_ ? 1 : 0},
      {"sender_mismatch_dropped", mismatch_.load()},
      {"sender_invalid_dropped", invalid_.load()}};
  for (size_t c = 0; c < dropped_by_channel_.size(); ++c) {
    out.emplace_back(std::string("dropped_") + SenderChannelName(static_cast<SenderChannel>(c)),
                     dropped_by_channel_[c].load());
  }
  return out;
}

bool SenderProofLog::First(const std::string& client, const std::string& participant) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::pair<std::string, std::string> key(client, participant);
  if (seen_.count(key) != 0) return false;
  if (seen_.size() >= kMaxRemembered) seen_.clear();
  seen_.insert(std::move(key));
  return true;
}

}  // namespace mostar::server
