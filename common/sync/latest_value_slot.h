// A one-element hand-over between a producer and a consumer thread that never queues: Put()
// replaces a value that was not taken yet and counts that as a drop. Used for frames the
// consumer (compression, network) cannot keep up with: they are dropped at the source.
//
// Thread-safe: any number of producers and consumers. Close() wakes every waiting Take() and
// makes later Take() calls return at once; Put() after Close() is ignored (not counted).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>

#include "common/time/time.h"

namespace mostar {

template <typename T>
class LatestValueSlot {
 public:
  struct Counters {
    uint64_t puts = 0;   // values offered
    uint64_t takes = 0;  // values handed to a consumer
    uint64_t drops = 0;  // values replaced before anybody took them
  };

  LatestValueSlot() = default;
  LatestValueSlot(const LatestValueSlot&) = delete;
  LatestValueSlot& operator=(const LatestValueSlot&) = delete;

  // Stores `value`, replacing (and dropping) an untaken one. Returns false when a value was
  // dropped or the slot is closed. Never blocks beyond the internal lock.
  bool Put(T value) {
    bool dropped = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (closed_) return false;
      ++counters_.puts;
      if (value_.has_value()) {
        ++counters_.drops;
        dropped = true;
      }
      value_ = std::move(value);
    }
    cv_.notify_one();
    return !dropped;
  }

  // Waits up to `timeout` for a value and removes it. Empty on timeout or when closed.
  std::optional<T> Take(Duration timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [this] { return closed_ || value_.has_value(); });
    return TakeLocked();
  }

  // Removes the value if there is one; never waits.
  std::optional<T> TryTake() {
    std::lock_guard<std::mutex> lock(mutex_);
    return TakeLocked();
  }

  void Close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
      value_.reset();
    }
    cv_.notify_all();
  }
  bool closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }
  Counters counters() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return counters_;
  }

 private:
  std::optional<T> TakeLocked() {
    if (closed_ || !value_.has_value()) return std::nullopt;
    std::optional<T> out = std::move(value_);
    value_.reset();
    ++counters_.takes;
    return out;
  }

  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::optional<T> value_;
  bool closed_ = false;
  Counters counters_;
};

}  // namespace mostar
