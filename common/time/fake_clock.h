// A manually advanced clock for tests: both `Now()` and `SteadyNow()` move only on `Advance`.
#pragma once

#include <mutex>

#include "common/time/time.h"

namespace mostar {

class FakeClock final : public Clock {
 public:
  explicit FakeClock(Time start = FromUnixNanos(1'700'000'000'000'000'000))
      : wall_(start), steady_(SteadyTime(Duration(1'000'000'000))) {}

  Time Now() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return wall_;
  }
  SteadyTime SteadyNow() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return steady_;
  }
  void Advance(Duration d) {
    std::lock_guard<std::mutex> lock(mutex_);
    wall_ += d;
    steady_ += d;
  }

 private:
  mutable std::mutex mutex_;
  Time wall_;
  SteadyTime steady_;
};

}  // namespace mostar
