// NTP-style estimate of the offset between two clocks from ping/pong exchanges.
//
// One exchange (a `ClockSample`): the *requester* stamps t0 when it sends a probe and t3 when
// the reply arrives (requester clock); the *responder* stamps t1 on receipt and t2 on reply
// (responder clock). Either side of the link can be the requester: the operator console probing
// the robot, or the robot probing each console.
//
//   offset     = ((t1 - t0) + (t2 - t3)) / 2   responder clock minus requester clock
//   round_trip = (t3 - t0) - (t2 - t1)         network time, responder processing removed
//
// With any (unknown, even asymmetric) one-way delays, the true offset lies within
// offset ± round_trip / 2 of a sample's offset. Queueing adds delay, never removes it, so the
// samples with the smallest round trip are the most accurate: the estimator keeps a window of
// recent samples and reports the offset of the one with the minimum round trip (the NTP clock
// filter), with half its round trip as the error bound.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>

#include "common/time/time.h"

namespace mostar::timesync {

struct ClockSample {
  Time t0;  // requester send, requester clock
  Time t1;  // responder receive, responder clock
  Time t2;  // responder send, responder clock
  Time t3;  // requester receive, requester clock
};

// Offset and round trip of one sample (no validity check).
Duration SampleOffset(const ClockSample& sample);     // responder minus requester
Duration SampleRoundTrip(const ClockSample& sample);  // may be negative for a corrupt sample

struct ClockOffsetEstimate {
  bool known = false;  // false until `min_samples` valid samples are in the window
  // Responder clock minus requester clock: responder_time = requester_time + offset.
  Duration responder_minus_requester{0};
  Duration round_trip{0};   // of the sample the offset comes from
  Duration uncertainty{0};  // bound on |estimate - true offset| = round_trip / 2
  size_t samples = 0;       // valid samples in the window

  // Converts a requester-clock instant to the responder clock, and back.
  Time ToResponderTime(Time requester_time) const {
    return requester_time + responder_minus_requester;
  }
  Time ToRequesterTime(Time responder_time) const {
    return responder_time - responder_minus_requester;
  }
};

struct ClockOffsetEstimatorOptions {
  size_t window_size = 16;  // most recent valid samples kept
  size_t min_samples = 3;   // valid samples needed before the estimate is `known`
  // Samples with a larger round trip are discarded (they carry little information).
  Duration max_round_trip = std::chrono::seconds(1);
  // Samples whose t3 is older than this relative to the newest t3 leave the window, so that
  // clock drift is followed. Zero disables age-based expiry.
  Duration max_sample_age = std::chrono::seconds(60);

  // False with a message naming the violated constraint.
  bool IsValid(std::string* error) const;
};

// One peer's estimator. Not thread-safe (the robot keeps one per client in
// robot_server/node/ClockResponder).
class ClockOffsetEstimator {
 public:
  explicit ClockOffsetEstimator(const ClockOffsetEstimatorOptions& options = {});

  // Adds an exchange. Returns false, counts it in `rejected()` and leaves the estimate
  // unchanged when the sample is inconsistent (t3 < t0, t2 < t1, negative round trip) or its
  // round trip exceeds `max_round_trip`.
  bool AddSample(const ClockSample& sample);

  ClockOffsetEstimate Estimate() const;
  uint64_t accepted() const { return accepted_; }
  uint64_t rejected() const { return rejected_; }
  // Forgets all samples (e.g. after the peer restarted); counters are kept.
  void Reset() { window_.clear(); }

 private:
  struct Entry {
    Time t3;
    Duration offset;
    Duration round_trip;
  };
  ClockOffsetEstimatorOptions options_;
  std::deque<Entry> window_;  // oldest first
  uint64_t accepted_ = 0;
  uint64_t rejected_ = 0;
};

}  // namespace mostar::timesync
