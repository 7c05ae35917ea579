#include "common/timesync/clock_offset_estimator.h"

#include <algorithm>

namespace mostar::timesync {

Duration SampleOffset(const ClockSample& s) { return ((s.t1 - s.t0) + (s.t2 - s.t3)) / 2; }

Duration SampleRoundTrip(const ClockSample& s) { return (s.t3 - s.t0) - (s.t2 - s.t1); }

bool ClockOffsetEstimatorOptions::IsValid(std::string* error) const {
  if (window_size < 1) {
    *error = "window_size must be at least 1";
    return false;
  }
  if (min_samples < 1 || min_samples > window_size) {
    *error = "min_samples must be in [1, window_size]";
    return false;
  }
  if (max_round_trip <= Duration::zero()) {
    *error = "max_round_trip must be positive";
    return false;
  }
  if (max_sample_age < Duration::zero()) {
    *error = "max_sample_age must not be negative";
    return false;
  }
  return true;
}

ClockOffsetEstimator::ClockOffsetEstimator(const ClockOffsetEstimatorOptions& options)
    : options_(options) {}

bool ClockOffsetEstimator::AddSample(const ClockSample& sample) {
  const Duration round_trip = SampleRoundTrip(sample);
  if (sample.t3 < sample.t0 || sample.t2 < sample.t1 || round_trip < Duration::zero() ||
      round_trip > options_.max_round_trip) {
    ++rejected_;
    return false;
  }
  ++accepted_;
  window_.push_back(Entry{sample.t3, SampleOffset(sample), round_trip});
  while (window_.size() > options_.window_size) window_.pop_front();
  if (options_.max_sample_age > Duration::zero()) {
    // A requester clock stepping backwards leaves the newest t3 below older ones: measure
    // age against the newest sample, which is always kept.
    const Time newest = window_.back().t3;
    while (window_.size() > 1 &&
           (newest - window_.front().t3 > options_.max_sample_age || window_.front().t3 > newest)) {
      window_.pop_front();
    }
  }
  return true;
}

ClockOffsetEstimate ClockOffsetEstimator::Estimate() const {
  ClockOffsetEstimate estimate;
  estimate.samples = window_.size();
  if (window_.empty()) return estimate;
  const auto best =
      std::min_element(window_.begin(), window_.end(),
                       [](const Entry& a, const Entry& b) { return a.round_trip < b.round_trip; });
  estimate.responder_minus_requester = best->offset;
  estimate.round_trip = best->round_trip;
  estimate.uncertainty = best->round_trip / 2;
  estimate.known = window_.size() >= options_.min_samples;
  return estimate;
}

}  // namespace mostar::timesync
