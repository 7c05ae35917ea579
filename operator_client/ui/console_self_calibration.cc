#include "operator_client/ui/console_self_calibration.h"

#include <cmath>

#include "common/check/check.h"

namespace mostar::ui {
namespace {

// How far (m) and how much (rad, wrapped) the robot moved from `a` to `b`.
double Moved(const Pose2D& a, const Pose2D& b) { return std::hypot(b.x_m - a.x_m, b.y_m - a.y_m); }
double Turned(const Pose2D& a, const Pose2D& b) {
  return std::abs(std::remainder(b.theta_rad - a.theta_rad, 2 * M_PI));
}

}  // namespace

bool ConsoleSelfCalibration::Options::IsValid(std::string* error) const {
  std::string why;
  if (window_points < 1 || window_age <= Duration::zero() || fit_period <= Duration::zero()) {
    why = "window_points, window_age and fit_period must be > 0";
  } else if (!(min_motion_m >= 0.0 && std::isfinite(min_motion_m)) ||
             !(min_turn_rad >= 0.0 && min_turn_rad < M_PI)) {
    why = "min_motion_m must be >= 0 and min_turn_rad in [0, pi)";
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
                                    const std::optional<Odometry>& odometry,
                                    const vision::VisionOptions& vision,
                                    const render::StereoGeometry& geometry) {
  if (!options_.enabled || !geometry.ready()) return;
  const math::LaserCameraCalibration& left = geometry.eye(0).image.calibration();
  in_force_ = calibration::ParametersOf(left);
  if (left.image_width_px != width_px_ || left.image_height_px != height_px_) {
    window_.Clear();  // pixels of another image size
    last_added_scan_.reset();
    last_added_pose_.reset();
    width_px_ = left.image_width_px;
    height_px_ = left.image_height_px;
  }
  if (!result || !result->ok || (seen_any_ && result->sequence == last_sequence_)) return;
  seen_any_ = true;
  last_sequence_ = result->sequence;
  const LaserScan& scan = result->scan;
  if (scan.ranges_m.empty()) return;
  const Time measured = result->placement.measured_stamp;
  const bool same_scan = last_added_scan_ && measured == *last_added_scan_;
  const bool still = odometry && last_added_pose_ &&
                     Moved(*last_added_pose_, odometry->pose) < options_.min_motion_m &&
                     Turned(*last_added_pose_, odometry->pose) < options_.min_turn_rad;
  if (same_scan || still) {
    ++repeated_results_;  // nothing new to learn
    return;
  }
  last_added_scan_ = measured;
  if (odometry) last_added_pose_ = odometry->pose;
  window_.Add(calibration::ExtractCorrespondences(*result, scan, vision.classifier,
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

bool ConsoleSelfCalibration::trustworthy_proposal() const {
  const std::shared_ptr<const calibration::FitResult> shown = proposal();
  return shown && shown->ok && shown->trustworthy;
}

bool ConsoleSelfCalibration::Apply(math::LaserCameraCalibration* live, std::string* message) {
  const std::shared_ptr<const calibration::FitResult> shown = proposal();  // one snapshot
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
