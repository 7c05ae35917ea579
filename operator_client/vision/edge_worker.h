// Runs the edge processing (VisionPipeline) of each stereo frame pair on its own thread, so the
// render loop never waits for OpenCV.
//
// Hand-over is a latest-value slot: Submit() stores the input and returns at once; an input not
// yet taken by the worker is replaced by a newer one (counted in Stats::replaced). Results are
// published as immutable snapshots tagged with the stamp and sequence of the images they were
// computed from, so the client draws each result over the frame it belongs to.
//
// Threading: every public method may be called from any thread. The destructor stops the worker
// (an input being processed is finished first; a pending one is discarded).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "common/sync/latest_value_slot.h"
#include "common/sync/wake_signal.h"
#include "common/time/time.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::vision {

class EdgeWorker {
 public:
  // What the worker runs on each input; the default is VisionPipeline::Process.
  using ProcessFunction = std::function<void(const VisionInput&, VisionResult*)>;

  struct Stats {
    uint64_t submitted = 0;  // Submit() calls
    uint64_t replaced = 0;   // inputs overwritten before the worker took them
    uint64_t processed = 0;  // results published (ok or not)
    uint64_t failed = 0;     // results with ok = false (bad input; see the result's error)
    Duration last_processing_time{0};
  };

  // `options` must be valid (asserted; check with IsValid() or use SetOptions()). `clock`
  // stamps VisionResult::published (not owned).
  explicit EdgeWorker(const VisionOptions& options, const Clock* clock = &SystemClock::Instance());
  // Runs `process` instead of the pipeline (tests, instrumentation). SetOptions() is refused.
  explicit EdgeWorker(ProcessFunction process, const Clock* clock = &SystemClock::Instance());
  ~EdgeWorker();

  EdgeWorker(const EdgeWorker&) = delete;
  EdgeWorker& operator=(const EdgeWorker&) = delete;

  // Hands over one frame pair; never blocks on processing.
  void Submit(VisionInput input);

  // Options for the inputs taken from now on (the edge-calibration view's sliders). Invalid
  // options are refused with `error` and the current ones kept.
  bool SetOptions(const VisionOptions& options, std::string* error);
  VisionOptions options() const;

  // Notified on the worker thread after each result is published (the render loop sleeps on
  // it). Not owned; must outlive the worker or be reset to nullptr.
  void SetWakeSignal(WakeSignal* signal);

  // The newest published result, or null before the first one. Cheap; never blocks on
  // processing.
  std::shared_ptr<const VisionResult> LatestResult() const;

  // Waits until at least `count` results have been published or `timeout` passes; true when
  // reached. For tests and orderly shutdown; the render loop polls LatestResult() instead.
  bool WaitForProcessed(uint64_t count, Duration timeout) const;

  Stats stats() const;

 private:
  void Run();

  ProcessFunction process_;
  const bool custom_process_;
  const Clock* clock_;
  LatestValueSlot<VisionInput> pending_;  // closed by the destructor
  mutable std::mutex mutex_;
  mutable std::condition_variable result_ready_;
  std::shared_ptr<VisionPipeline> pipeline_;    // guarded by mutex_; used by the worker only
  std::shared_ptr<const VisionResult> latest_;  // guarded by mutex_
  WakeSignal* wake_ = nullptr;                  // guarded by mutex_
  Stats stats_;         // guarded by mutex_ (submitted and replaced come from pending_)
  std::thread thread_;  // last: starts after the rest exists
};

}  // namespace mostar::vision
