#include "operator_client/ui/console_self_calibration.h"

#include "common/check/check.h"

namespace mostar::ui {

bool ConsoleSelfCalibration::Options::IsValid(std::string* error) const {
  std::string why;
  if (window_points < 1 || window_age <= Duration::zero() || fit_period <= Duration::zero()) {
    why = "window_points, window_age and fit_period must be > 0";
  } else if (!correspondences.IsValid(&why)) {
    why = "correspondences: " + why;
  } else if (!fit.IsValid(&why)) {
    why = "fit: " + why;
  } else {
    return true;
  }
  if (error != nullptr) *error = why;
  return false;
}

ConsoleSelfCalibration::ConsoleSelfCalibration(const Options& options)
    : options_(options), window_(options.window_points, options.window_age), worker_(options.fit) {
  MOSTAR_CHECK(options_.IsValid(nullptr));
}

void ConsoleSelfCalibration::Update(const std::shared_ptr<const vision::VisionResult>& result,
                                    const NearestScan& nearest_scan,
                                    const vision::VisionOptions& vision,
                                    const render::StereoGeometry& geometry) {
  if (!options_.enabled || !geometry.ready()) return;
  const math::LaserCameraCalibration& left = geometry.eye(0).image.calibration();
  in_force_ = calibration::ParametersOf(left);
  if (left.image_width_px != width_px_ || left.image_height_px != height_px_) {
    window_.Clear();  // pixels of another image size
    width_px_ = left.image_width_px;
    height_px_ = left.image_height_px;
  }
  if (!result || !result->ok || (seen_any_ && result->sequence == last_sequence_)) return;
  seen_any_ = true;
  last_sequence_ = result->sequence;
  const std::optional<LaserScan> scan = nearest_scan(result->stamp);
  if (!scan) return;
  window_.Add(calibration::ExtractCorrespondences(*result, *scan, vision.classifier,
                                                  left.laser_height_m, options_.correspondences));
  if (!last_fit_stamp_) last_fit_stamp_ = result->stamp;  // the first fit after one period
  if (result->stamp >= *last_fit_stamp_ && result->stamp < *last_fit_stamp_ + options_.fit_period) {
    return;
  }
  last_fit_stamp_ = result->stamp;
  calibration::FitInput input;
  input.left = left;
  input.right = geometry.eye(1).image.calibration();
  input.points = window_.Snapshot();
  worker_.Submit(std::move(input));
}

std::shared_ptr<const calibration::FitResult> ConsoleSelfCalibration::proposal() const {
  std::shared_ptr<const calibration::FitResult> latest = worker_.LatestResult();
  if (!latest || latest == rejected_ || calibration::ParametersOf(latest->start) != in_force_) {
    return nullptr;
  }
  return latest;
}

bool ConsoleSelfCalibration::Apply(math::LaserCameraCalibration* live, std::string* message) {
  const std::shared_ptr<const calibration::FitResult> shown = proposal();
  if (!shown || !shown->ok || !shown->trustworthy) {
    *message = "self-calibration: no trustworthy proposal to apply";
    return false;
  }
  const math::LaserCameraCalibration moved = calibration::MoveParameters(
      *live, calibration::ParametersOf(shown->start), calibration::ParametersOf(shown->proposal));
  std::string error;
  if (!moved.IsValid(&error)) {
    *message = "self-calibration: " + error;
    return false;
  }
  *live = moved;
  rejected_ = shown;  // applied: not shown again
  *message = "self-calibration applied";
  return true;
}

void ConsoleSelfCalibration::Reject() { rejected_ = worker_.LatestResult(); }

}  // namespace mostar::ui
