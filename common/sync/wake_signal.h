// Wakes a loop that sleeps until something it shows has changed (a decoded stereo pair, an edge
// result): producers call Notify(), the loop calls WaitFor() when it has nothing new to do.
// A notification is never lost: one that comes while the loop is busy makes the next WaitFor()
// return at once. Several notifications before a wait count as one.
//
// Thread-safe. Notify() never blocks for long; the hook set by SetHook() (e.g. a call that wakes
// a window's event wait) runs in Notify(), on the notifying thread, without the signal's lock.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <utility>

#include "common/time/time.h"

namespace mostar {

class WakeSignal {
 public:
  WakeSignal() = default;
  WakeSignal(const WakeSignal&) = delete;
  WakeSignal& operator=(const WakeSignal&) = delete;

  void Notify() {
    std::function<void()> hook;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pending_ = true;
      ++notifications_;
      hook = hook_;
    }
    cv_.notify_all();
    if (hook) hook();
  }

  // Waits until a notification not yet consumed or `timeout`; true when notified (and consumes
  // it). Returns at once when one is pending.
  bool WaitFor(Duration timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    const bool notified = cv_.wait_for(lock, timeout, [this] { return pending_; });
    pending_ = false;
    return notified;
  }

  // Consumes a pending notification without waiting; true when there was one.
  bool TakePending() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::exchange(pending_, false);
  }

  // Called by every later Notify(); set before producers start, or accept that a Notify()
  // running during the call may still use the previous hook.
  void SetHook(std::function<void()> hook) {
    std::lock_guard<std::mutex> lock(mutex_);
    hook_ = std::move(hook);
  }

  uint64_t notifications() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return notifications_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  bool pending_ = false;
  uint64_t notifications_ = 0;
  std::function<void()> hook_;
};

}  // namespace mostar
