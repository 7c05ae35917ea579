// A bound on a part of a program's teardown that can block inside a library where no orderly
// end can be forced (Fast DDS 2.9: a participant's TCP transport joining its threads, a writer
// waiting for acknowledgements while its entities are deleted): if the guarded part has not
// finished when the deadline passes, the process ends at once with a message on stderr and the
// given exit status, instead of hanging until someone kills it.
//
// Arm it only once everything that must not be cut short is done (motors stopped, e-stop latch
// recorded). Threading: one waiting thread per armed deadline; the destructor disarms it and
// returns at once (it never waits for the deadline).
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "common/time/time.h"

namespace mostar {

class ExitDeadline {
 public:
  // Ends the process with std::_Exit(exit_code) after `timeout`, printing
  // "<program>: <what> did not finish within <timeout, 2 decimals> s: ending now (exit status
  // <code>)".
  ExitDeadline(Duration timeout, int exit_code, std::string program, std::string what);
  // Calls `on_expiry` (on the waiting thread) after `timeout` unless destroyed first (tests).
  ExitDeadline(Duration timeout, std::function<void()> on_expiry);
  ~ExitDeadline();

  ExitDeadline(const ExitDeadline&) = delete;
  ExitDeadline& operator=(const ExitDeadline&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable disarmed_cv_;
  bool disarmed_ = false;  // guarded by mutex_
  std::thread waiter_;
};

}  // namespace mostar
