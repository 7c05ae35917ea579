// Which observers' emergency stops mostar_relay passes on to the robot.
//
// Observers behind the relay have no path to the robot, yet anyone watching must be able to
// stop it. The relay passes engagements only, under its own client id (the robot's role table
// lists the relay as an observer; with DDS Security the id is the relay's certificate name),
// and at most one per `min_interval`: observers repeat theirs until the robot reports the stop,
// and the robot needs only one. Releases are never passed: only the lease holder, who talks to
// the robot directly, may release (docs/safety.md). Pure and single-threaded: the relay calls
// it from one DDS receive thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "common/time/time.h"
#include "common/types/commands.h"

namespace mostar::relay {

struct EstopForwardingStats {
  uint64_t received = 0;          // e-stops heard from observers
  uint64_t forwarded = 0;         // engagements written towards the robot
  uint64_t releases_refused = 0;  // releases, never forwarded
  uint64_t rate_limited = 0;      // engagements within min_interval of the last forwarded one
};

class EstopForwarding {
 public:
  EstopForwarding(std::string relay_id, Duration min_interval)
      : relay_id_(std::move(relay_id)), min_interval_(min_interval) {}

  // The e-stop to write towards the robot for `received` (from an observer), stamped `now`
  // (the relay's clock, like any client's), or nullopt. `steady_now` is monotonic.
  std::optional<EmergencyStop> OnObserverEstop(const EmergencyStop& received, Time now,
                                               SteadyTime steady_now);

  const EstopForwardingStats& stats() const { return stats_; }

 private:
  const std::string relay_id_;
  const Duration min_interval_;
  std::optional<SteadyTime> last_forwarded_;
  EstopForwardingStats stats_;
};

}  // namespace mostar::relay
