// Edge processing for the console (thesis 8, 9.2): hands each new decoded pair, with the scan
// nearest in time moved to the pair's capture time (PlaceScanForVision) and the overlay's
// potential outliers, to the edge worker; picks the pair and
// result to show (FramePicker); gives NESC's vertical offset hint while it is current; takes
// the edge view's live settings. Render thread only; never waits for the worker. No GL.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "common/math/camera_model.h"
#include "common/types/laser_scan.h"
#include "operator_client/fusion/ar_features.h"
#include "operator_client/ui/frame_picker.h"
#include "operator_client/ui/stereo_hint.h"
#include "operator_client/ui/vision_settings.h"
#include "operator_client/video/stereo_receiver.h"
#include "operator_client/vision/edge_worker.h"

namespace mostar::ui {

class ConsoleVision {
 public:
  // A scan as edge processing is to see it with a pair.
  struct PlacedScan {
    LaserScan scan;
    vision::ScanPlacement placement;
  };
  // The scan for a capture stamp (robot clock): the one nearest in time, placed by
  // PlaceScanForVision (at that time when it can be moved there); nullopt when there is none.
  using ScanForImage = std::function<std::optional<PlacedScan>(Time stamp)>;

  // `options` must be valid (VisionOptions::IsValid).
  explicit ConsoleVision(const vision::VisionOptions& options);
  // Runs `process` instead of the pipeline (tests); settings changes are then refused.
  ConsoleVision(const vision::VisionOptions& options, vision::EdgeWorker::ProcessFunction process);

  // The eyes' image models changed (calibration, alignment): pairs from now on use these, and a
  // hint from a pair handed over before the change is stale.
  void GeometryChanged(std::shared_ptr<const math::CameraModel> left,
                       std::shared_ptr<const math::CameraModel> right);

  // One render tick at `now` (this machine's monotonic clock). `enabled` false: the latest pair
  // is shown as it is. Else a new pair goes to the worker with its scan (`scan_for`) and
  // `outliers_of` that scan's potential-outlier labels (the overlay's builder, so a live slopeTh
  // edit moves what edges confirm), and the shown pair follows the results and the result wait
  // (FramePicker).
  void Update(const std::optional<client::DecodedStereoPair>& latest, bool enabled, SteadyTime now,
              const ScanForImage& scan_for, const fusion::ArFeatureBuilder& outliers_of);

  // How long a new pair waits for its edge result before it is shown without it (>= 0).
  void SetResultWait(Duration wait) { result_wait_ = wait; }
  Duration result_wait() const { return result_wait_; }
  // When the render loop must look again although nothing was notified: the end of the newest
  // pair's result wait; nullopt when no pair waits.
  std::optional<SteadyTime> NextWaitEnd() const { return picker_.NextWaitEnd(result_wait_); }
  // Notified when a result is published (not owned; outlives this object or reset to nullptr).
  void SetWakeSignal(WakeSignal* signal) { worker_.SetWakeSignal(signal); }

  const FramePicker& picker() const { return picker_; }

  // NESC's vertical offset suggestion from the shown result, when it is stereo, valid and
  // computed with the current geometry. `suggest` turns NESC's residual (px) into the right
  // eye's offset (render::SuggestedRightOffsetY).
  std::optional<StereoOffsetHint> OffsetHint(
      const std::function<float(double residual_px)>& suggest) const;

  const VisionSettings& settings() const { return settings_; }
  // The edge view's new settings for the pairs handed over from now on; false with a message,
  // and the current ones kept, when the worker refuses them.
  bool ApplySettings(const VisionSettings& next, std::string* error);

 private:
  vision::EdgeWorker worker_;
  VisionSettings settings_;
  std::shared_ptr<const math::CameraModel> left_model_;  // shared with the worker's ray cache
  std::shared_ptr<const math::CameraModel> right_model_;
  uint64_t last_submitted_ = 0;  // sequence of the last pair handed to the worker
  Duration result_wait_ = std::chrono::milliseconds(10);
  StereoHintGate hint_gate_;
  FramePicker picker_;
};

}  // namespace mostar::ui
