// Who may drive: exactly one pilot at a time, decided on the robot.
//
// Rules:
// - Roles and strengths come from the server-side role table, never from the request (the
//   `strength` field of a ControlRequest is ignored). Ids not in the table are observers. The
//   table is keyed by client id: with DDS Security the CN of the client's certificate, which
//   RobotNode has checked each request's sender_id against.
// - Observers never hold the lease.
// - A pilot takes a free lease. A held lease changes hands only when the holder releases it or
//   a strictly stronger pilot takes it over; equal or weaker requests are refused.
// - When the holder's liveliness is lost nobody holds the lease: a waiting pilot must ask
//   again, nobody inherits motion. Liveliness is lost on a DDS liveliness/deadline event (fed in
//   by the wiring through OnLivelinessLost) or when the holder was not heard from (NoteAlive:
//   accepted commands, its own requests) for `holder_timeout` since the grant or the last sign
//   of life (ExpireSilentHolder, called by the control loop).
// - Every change stamps `since` with the clock and increments `lease_sequence`.
// - E-stop: any client in the role table (pilot or observer) may engage it; only the lease
//   holder may release it (a pilot takes the lease first if nobody holds it). Observers never
//   release it, even one that engaged it.
// Thread-safe.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "common/time/time.h"
#include "common/types/commands.h"

namespace mostar::drive {

enum class Role : uint8_t { kObserver = 0, kPilot = 1 };
const char* RoleName(Role role);

struct RoleEntry {
  Role role = Role::kObserver;
  int32_t strength = 0;  // meaningful for pilots; higher wins a take-over
};

// Client id -> role. Unknown ids are observers with strength 0 and are not `Known`.
class RoleTable {
 public:
  void Set(const std::string& client_id, RoleEntry entry) { entries_[client_id] = entry; }
  RoleEntry Lookup(const std::string& client_id) const;
  bool Known(const std::string& client_id) const { return entries_.count(client_id) > 0; }
  size_t size() const { return entries_.size(); }

 private:
  std::map<std::string, RoleEntry> entries_;
};

enum class LeaseDecision : uint8_t {
  kGranted = 0,           // the requester now holds the lease (or already did)
  kReleased = 1,          // the holder released it: nobody holds it
  kRefusedObserver = 2,   // observers never drive
  kRefusedHeld = 3,       // held by an equal or stronger pilot
  kRefusedNotHolder = 4,  // release from someone who does not hold the lease
};
const char* LeaseDecisionName(LeaseDecision decision);

struct PilotLeaseStats {
  uint64_t granted = 0;
  uint64_t takeovers = 0;
  uint64_t released = 0;
  uint64_t refused = 0;
  uint64_t holder_lost = 0;
};

class PilotLease {
 public:
  static constexpr Duration kDefaultHolderTimeout = std::chrono::seconds(2);
  // `holder_timeout` > 0: silence after which the holder loses the lease.
  PilotLease(const Clock& clock, RoleTable roles, Duration holder_timeout = kDefaultHolderTimeout);

  LeaseDecision HandleRequest(const ControlRequest& request);
  // The client's liveliness was lost. Returns true when it held the lease (now free).
  bool OnLivelinessLost(const std::string& client_id);
  // A sign of life from `client_id` (steady clock now); only the holder's count.
  void NoteAlive(const std::string& client_id);
  // Frees the lease when its holder has been silent for more than `holder_timeout` at `now`;
  // returns the id of the holder that lost it.
  std::optional<std::string> ExpireSilentHolder(SteadyTime now);
  Duration holder_timeout() const { return holder_timeout_; }

  ControlLease lease() const;  // `stamp` = now
  std::string holder() const;
  bool IsHolder(const std::string& client_id) const;
  bool MayEngageEstop(const std::string& client_id) const;
  bool MayReleaseEstop(const std::string& client_id) const;
  Role RoleOf(const std::string& client_id) const;
  PilotLeaseStats stats() const;

 private:
  void ChangeHolderLocked(const std::string& holder_id, int32_t strength);

  const Clock& clock_;
  const RoleTable roles_;
  const Duration holder_timeout_;
  mutable std::mutex mutex_;
  ControlLease lease_;
  SteadyTime holder_heard_;  // grant or last sign of life of the holder
  PilotLeaseStats stats_;
};

}  // namespace mostar::drive
