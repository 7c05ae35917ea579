// Edge processing for mostar_web: decodes both eyes of a pair's JPEGs and runs the console's
// vision::VisionPipeline on them (the work the console's EdgeWorker does on decoded pairs), on a
// thread of its own, so composing frames for browsers never waits for JPEG decoding or OpenCV.
//
// Hand-over is a latest-value slot: Submit() stores the job and returns at once; a job not yet
// taken is replaced by a newer one (counted). Each result is published as an immutable snapshot
// tagged with the job's sequence, so the caller draws it over the pair it belongs to only.
// Each JPEG's header is read first: one declaring more pixels than its camera model's image is
// refused before decoding (counted in `broken`, as an undecodable one).
//
// Threading: every public method may be called from any thread. The destructor stops the worker
// (a job being processed is finished first; a pending one is discarded).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "common/math/camera_model.h"
#include "common/sync/latest_value_slot.h"
#include "common/time/time.h"
#include "common/types/laser_scan.h"
#include "common/types/stereo_frame.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::web {

struct EdgeJob {
  uint64_t sequence = 0;                 // the frame's sequence: the result carries it back
  CompressedStereoPair pair;             // both eyes' JPEGs (the right may be empty in mono)
  LaserScan scan;                        // nearest to the pair's stamp, placed for edge
  vision::ScanPlacement placement;       // processing (ui::PlaceScanForVision)
  std::vector<bool> potential_outliers;  // one per beam of `scan` (FrameComposer)
  std::shared_ptr<const math::CameraModel> left_camera;   // the eyes' image models in force
  std::shared_ptr<const math::CameraModel> right_camera;  // may be null in mono
};

class EdgeRunner {
 public:
  struct Stats {
    uint64_t submitted = 0;
    uint64_t replaced = 0;        // jobs overwritten before the worker took them
    uint64_t processed = 0;       // results published (ok or not)
    uint64_t failed = 0;          // results with ok = false (vision refused the input)
    uint64_t broken = 0;          // pairs not decoded (bad or oversized JPEG): no result
    Duration decode_time{0};      // of the last pair, both eyes
    Duration processing_time{0};  // of the last VisionPipeline::Process
  };

  // `options` must be valid (asserted).
  explicit EdgeRunner(const vision::VisionOptions& options);
  ~EdgeRunner();
  EdgeRunner(const EdgeRunner&) = delete;
  EdgeRunner& operator=(const EdgeRunner&) = delete;

  // Never blocks on processing.
  void Submit(EdgeJob job);
  // The newest published result, or null before the first. Never blocks on processing.
  std::shared_ptr<const vision::VisionResult> LatestResult() const;
  Stats stats() const;

 private:
  void Run();

  vision::VisionPipeline pipeline_;  // used by the worker only
  LatestValueSlot<EdgeJob> pending_;
  mutable std::mutex mutex_;
  std::shared_ptr<const vision::VisionResult> latest_;  // guarded by mutex_
  Stats stats_;                                         // guarded by mutex_
  std::thread thread_;                                  // last: starts after the rest exists
};

}  // namespace mostar::web
