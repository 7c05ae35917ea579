// Runs calibration fits (calibration_fit.h) on their own thread, so the render loop never waits
// for the solver. Hand-over as in vision::EdgeWorker: Submit() stores the request in a
// latest-value slot and returns at once (a request not yet taken is replaced); results are
// published as immutable snapshots.
//
// Threading: every public method may be called from any thread. The destructor stops the
// worker (a fit being computed is finished first; its work is bounded by FitOptions).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "common/sync/latest_value_slot.h"
#include "common/time/time.h"
#include "operator_client/calibration/calibration_fit.h"

namespace mostar::calibration {

class FitWorker {
 public:
  // `options` must be valid (asserted).
  explicit FitWorker(const FitOptions& options);
  ~FitWorker();

  FitWorker(const FitWorker&) = delete;
  FitWorker& operator=(const FitWorker&) = delete;

  // Hands over one fit request; never blocks on fitting.
  void Submit(FitInput input);
  // The newest result, or null before the first one; never blocks on fitting.
  std::shared_ptr<const FitResult> LatestResult() const;
  // Results published so far.
  uint64_t completed() const;
  // Waits until `count` results have been published or `timeout` passes (tests, shutdown).
  bool WaitForCompleted(uint64_t count, Duration timeout) const;

 private:
  void Run();

  const FitOptions options_;
  LatestValueSlot<FitInput> pending_;  // closed by the destructor
  mutable std::mutex mutex_;
  mutable std::condition_variable done_;
  std::shared_ptr<const FitResult> latest_;  // guarded by mutex_
  uint64_t completed_ = 0;                   // guarded by mutex_
  std::thread thread_;                       // last: starts after the rest exists
};

}  // namespace mostar::calibration
