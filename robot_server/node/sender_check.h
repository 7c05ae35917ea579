// Whether a command, control request, e-stop or clock ping may be believed to come from the
// client its `sender_id` names.
//
// With DDS Security (identities verified) a sample counts only when its sender_id is the client
// id of the authenticated participant that wrote it (its certificate's CN,
// common/dds/security.h); otherwise it is dropped: kMismatch when the writer is another
// client, kUnidentified when the writer's participant has no verified client id. Without DDS
// Security nothing can be verified: samples pass as kUnverified and the robot's health says so
// (identities_verified = 0). A sender_id that is no valid client id is dropped either way.
// Drops are counted per reason and per channel. Thread-safe (atomic counters).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mostar::server {

enum class SenderChannel : uint8_t { kCommand = 0, kEmergencyStop, kControlRequest, kClockPing };
const char* SenderChannelName(SenderChannel channel);

enum class SenderVerdict : uint8_t {
  kVerified = 0,  // sender_id is the writer's authenticated client id
  kUnverified,    // no DDS Security: sender_id taken as written
  kMismatch,      // the writer is authenticated as another client
  kUnidentified,  // DDS Security on, but the writer has no verified client id
  kInvalidId,     // sender_id is no valid client id
};
const char* SenderVerdictName(SenderVerdict verdict);

class SenderCheck {
 public:
  explicit SenderCheck(bool identities_verified) : identities_verified_(identities_verified) {}

  // `authenticated`: the client id of the participant that wrote the sample (nullopt when
  // unknown). Counts the verdict.
  SenderVerdict Check(SenderChannel channel, const std::string& sender_id,
                      const std::optional<std::string>& authenticated);
  static bool Admits(SenderVerdict verdict) {
    return verdict == SenderVerdict::kVerified || verdict == SenderVerdict::kUnverified;
  }

  bool identities_verified() const { return identities_verified_; }
  // Samples dropped so far, all channels and reasons.
  uint64_t dropped() const;
  // For the "network" health device: identities_verified (1/0), drops per reason
  // (sender_mismatch_dropped, sender_unidentified_dropped, sender_invalid_dropped) and per
  // channel (dropped_cmd_vel, dropped_estop, dropped_control_request, dropped_clock_ping).
  std::vector<std::pair<std::string, uint64_t>> HealthCounters() const;

 private:
  const bool identities_verified_;
  std::atomic<uint64_t> mismatch_{0};
  std::atomic<uint64_t> unidentified_{0};
  std::atomic<uint64_t> invalid_{0};
  std::array<std::atomic<uint64_t>, 4> dropped_by_channel_{};
};

}  // namespace mostar::server
