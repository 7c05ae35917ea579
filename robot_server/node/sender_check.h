// Whether a command, control request, e-stop or clock ping may be believed to come from the
// client its `sender_id` names.
//
// The robot reads each client of its role table in that client's own DDS partition
// (common/identity/sender_partition.h), so every sample comes with the client id of the
// partition it arrived in. With DDS Security that id is proven: the permissions of the
// certificate that authenticated in the handshake allow it to write in its own partition only,
// and Fast DDS' access control matches no other writer there. A sample counts only when its
// sender_id is that id; otherwise it is dropped (kMismatch). Nothing a participant announces
// (its GUID, the certificate in its USER_DATA) enters the decision. Without DDS Security the
// partition is as much a claim as the sender_id: samples whose ids agree pass as kUnverified and
// the robot's health says so (identities_verified = 0). A sender_id that is no valid client id
// is dropped either way. Drops are counted per reason and per channel. Thread-safe (atomic
// counters).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace mostar::server {

enum class SenderChannel : uint8_t { kCommand = 0, kEmergencyStop, kControlRequest, kClockPing };
const char* SenderChannelName(SenderChannel channel);

enum class SenderVerdict : uint8_t {
  kVerified = 0,  // sender_id is the client whose partition it came in, proven by permissions
  kUnverified,    // no DDS Security: the ids agree but prove nothing
  kMismatch,      // sender_id is not the client whose partition it came in
  kInvalidId,     // sender_id is no valid client id
};
const char* SenderVerdictName(SenderVerdict verdict);

class SenderCheck {
 public:
  explicit SenderCheck(bool identities_verified) : identities_verified_(identities_verified) {}

  // `partition_client`: the client id of the partition the sample arrived in. Counts the
  // verdict.
  SenderVerdict Check(SenderChannel channel, const std::string& sender_id,
                      const std::string& partition_client);
  static bool Admits(SenderVerdict verdict) {
    return verdict == SenderVerdict::kVerified || verdict == SenderVerdict::kUnverified;
  }

  bool identities_verified() const { return identities_verified_; }
  // Samples dropped so far, all channels and reasons.
  uint64_t dropped() const;
  // For the "network" health device: identities_verified (1/0), drops per reason
  // (sender_mismatch_dropped, sender_invalid_dropped) and per channel (dropped_cmd_vel,
  // dropped_estop, dropped_control_request, dropped_clock_ping).
  std::vector<std::pair<std::string, uint64_t>> HealthCounters() const;

 private:
  const bool identities_verified_;
  std::atomic<uint64_t> mismatch_{0};
  std::atomic<uint64_t> invalid_{0};
  std::array<std::atomic<uint64_t>, 4> dropped_by_channel_{};
};

// Which participants have shown to be which client: a writer of theirs matched in the client's
// partition (with DDS Security, only the client's signed permissions allow that). The robot logs
// each (client, participant) pair once, the first time; at most kMaxRemembered pairs are kept
// (all forgotten at once beyond, then logged again). Thread-safe.
class SenderProofLog {
 public:
  static constexpr size_t kMaxRemembered = 1024;
  // True the first time `participant` (a GUID prefix, any printable form) writes in `client`'s
  // partition.
  bool First(const std::string& client, const std::string& participant);

 private:
  std::mutex mutex_;
  std::set<std::pair<std::string, std::string>> seen_;
};

}  // namespace mostar::server
