// When the tunnel client starts its next dial (pure: the clock comes in as arguments).
//
// A path that died answers nothing: a SYN sent into it is retransmitted by TCP only after 1 s,
// then 3 s, so one dial at a time would follow the path back a second or more late. Instead,
// while no dial has an answer, a new one starts every `interval` beside those in flight (each
// its own socket, at most `max_in_flight`), so the first SYN sent after the path is back
// connects: the tunnel follows the link within about `interval` plus a round trip, whatever
// the round trip. A dial that gets an answer (refused, unreachable, the name not found, a
// connection that ended) means the path is there but the hub is not ready: the next waits a
// backoff from `initial_backoff` doubling to `max_backoff`, reset by a connection.
#pragma once

#include <chrono>

namespace mostar::udp_over_tcp {

struct DialPlanOptions {
  std::chrono::milliseconds interval{250};
  int max_in_flight = 6;
  std::chrono::milliseconds initial_backoff{250};
  std::chrono::milliseconds max_backoff{1000};
};

class DialPlan {
 public:
  using Clock = std::chrono::steady_clock;
  explicit DialPlan(DialPlanOptions options);

  // Whether a new dial may start now with `in_flight` dials pending.
  bool ShouldDial(Clock::time_point now, int in_flight) const;
  // A dial started at `now`.
  void Started(Clock::time_point now);
  // A dial or connection failed with an answer from the path: back off. Returns the wait.
  std::chrono::milliseconds Answered(Clock::time_point now);
  // A connection is up: the next outage starts with the shortest waits.
  void Connected();
  // When ShouldDial can next turn true (for the event loop's poll timeout).
  Clock::time_point next_dial() const { return next_dial_; }

 private:
  DialPlanOptions options_;
  Clock::time_point next_dial_{};
  std::chrono::milliseconds backoff_;
};

}  // namespace mostar::udp_over_tcp
