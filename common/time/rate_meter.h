// Measures an event rate (Hz) over a sliding window of monotonic time. Not thread-safe.
#pragma once

#include <deque>

#include "common/time/time.h"

namespace mostar {

class RateMeter {
 public:
  explicit RateMeter(Duration window = std::chrono::seconds(2)) : window_(window) {}

  void Tick(SteadyTime now) {
    stamps_.push_back(now);
    Trim(now);
  }
  // Events per second over the window ending at `now`; 0 with fewer than two events.
  double RateHz(SteadyTime now) {
    Trim(now);
    if (stamps_.size() < 2) return 0.0;
    const double span = ToSeconds(stamps_.back() - stamps_.front());
    return span > 0 ? static_cast<double>(stamps_.size() - 1) / span : 0.0;
  }

 private:
  void Trim(SteadyTime now) {
    while (!stamps_.empty() && now - stamps_.front() > window_) stamps_.pop_front();
  }
  Duration window_;
  std::deque<SteadyTime> stamps_;
};

}  // namespace mostar
