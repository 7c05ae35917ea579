// The robot's side of the clock pings (NTP style, common/timesync): each ping is answered by a
// pong with the robot's receive (t1) and send (t2) stamps, and the client's previous exchange is
// completed with its receive time of that pong (the t3 the next ping carries), which gives the
// client's clock offset.
//
// Keyed by the client id the robot admitted (with DDS Security: the writer's certificate CN,
// RobotNode), so nobody else's pings reach a client's estimate. At most `max_clients` clients
// are tracked; a new one replaces the client heard from least recently (counted). Forget drops a
// client's exchanges and estimate (RobotNode does it when the lease changes hands). Thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "common/time/time.h"
#include "common/timesync/clock_offset_estimator.h"
#include "common/types/commands.h"

namespace mostar::server {

class ClockResponder {
 public:
  // `max_clients` >= 1 (checked).
  explicit ClockResponder(const Clock& clock, size_t max_clients = 32,
                          timesync::ClockOffsetEstimatorOptions estimator = {});

  // The pong to `ping` from `client_id`, which arrived at `received` (robot clock); its t2 is
  // stamped now.
  ClockProbe Answer(const std::string& client_id, const ClockProbe& ping, Time received);
  // Robot clock minus the client's clock, once known.
  std::optional<Duration> RobotMinusClient(const std::string& client_id) const;
  void Forget(const std::string& client_id);

  size_t clients() const;
  uint64_t evicted() const;

 private:
  struct Client {
    timesync::ClockOffsetEstimator estimator;
    std::optional<ClockProbe> last_pong;
    uint64_t last_heard = 0;  // order of the last ping
  };

  const Clock& clock_;
  const size_t max_clients_;
  const timesync::ClockOffsetEstimatorOptions estimator_options_;
  mutable std::mutex mutex_;
  std::map<std::string, Client> clients_;
  uint64_t pings_ = 0;
  uint64_t evicted_ = 0;
};

}  // namespace mostar::server
