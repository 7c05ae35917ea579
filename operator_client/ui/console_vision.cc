#include "operator_client/ui/console_vision.h"

#include <utility>

#include "operator_client/ui/ar_builder_cache.h"

namespace mostar::ui {

ConsoleVision::ConsoleVision(const vision::VisionOptions& options)
    : worker_(options), settings_(options) {}

ConsoleVision::ConsoleVision(const vision::VisionOptions& options,
                             vision::EdgeWorker::ProcessFunction process)
    : worker_(std::move(process)), settings_(options) {}

void ConsoleVision::GeometryChanged(std::shared_ptr<const math::CameraModel> left,
                                    std::shared_ptr<const math::CameraModel> right) {
  hint_gate_.GeometryChanged(last_submitted_);
  left_model_ = std::move(left);
  right_model_ = std::move(right);
}

void ConsoleVision::Update(const std::optional<client::DecodedStereoPair>& latest, bool enabled,
                           SteadyTime now, const ScanForImage& scan_for,
                           const fusion::ArFeatureBuilder& outliers_of) {
  if (!enabled) {
    picker_.ShowUnprocessed(latest);
    return;
  }
  if (picker_.TakeNew(latest, now)) {
    vision::VisionInput input;
    input.stamp = latest->stamp;
    input.sequence = latest->sequence;
    input.left = latest->left;
    input.right = latest->right;
    if (std::optional<PlacedScan> placed = scan_for(latest->stamp)) {
      input.potential_outliers = PotentialOutliers(outliers_of, placed->scan);
      input.scan = std::move(placed->scan);
      input.placement = std::move(placed->placement);
    }
    input.left_camera = left_model_;
    input.right_camera = right_model_;
    last_submitted_ = input.sequence;
    worker_.Submit(std::move(input));
  }
  picker_.OnResult(worker_.LatestResult(), latest, now, result_wait_);
}

std::optional<StereoOffsetHint> ConsoleVision::OffsetHint(
    const std::function<float(double residual_px)>& suggest) const {
  const std::shared_ptr<const vision::VisionResult>& result = picker_.shown_result();
  if (!result || !result->ok || !result->stereo) return std::nullopt;
  const vision::StereoOffsetEstimate& estimate = result->nesc.offset;
  return hint_gate_.Hint(result->sequence, estimate, suggest(estimate.vertical_offset_px));
}

bool ConsoleVision::ApplySettings(const VisionSettings& next, std::string* error) {
  if (!worker_.SetOptions(next.options(), error)) return false;
  settings_ = next;
  return true;
}

}  // namespace mostar::ui
