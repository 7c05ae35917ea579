#include "operator_client/ui/intrinsics_adoption.h"

namespace mostar::ui {

namespace {

bool SameIntrinsics(const CameraIntrinsicsInfo& a, const CameraIntrinsicsInfo& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy &&
         a.distortion == b.distortion;
}

}  // namespace

bool WithRobotIntrinsics(const math::LaserCameraCalibration& calibration,
                         const CameraIntrinsicsInfo& k, math::LaserCameraCalibration* out,
                         std::string* error) {
  if (k.width_px != calibration.image_width_px || k.height_px != calibration.image_height_px) {
    *error = "robot intrinsics are for " + std::to_string(k.width_px) + "x" +
             std::to_string(k.height_px) + " images: not used";
    return false;
  }
  math::LaserCameraCalibration next = calibration;
  next.focal_px = k.fx;
  next.focal_y_px = k.fy;
  next.principal_x_px = k.cx;
  next.principal_y_px = k.cy;
  const auto d = [&k](size_t i) { return i < k.distortion.size() ? k.distortion[i] : 0.0; };
  next.distortion = {d(0), d(1), d(2), d(3), d(4)};
  std::string invalid;
  if (!next.IsValid(&invalid)) {
    *error = "robot intrinsics refused: " + invalid;
    return false;
  }
  *out = next;
  return true;
}

math::LaserCameraCalibration RightEyeCalibration(const math::LaserCameraCalibration& shared,
                                                 const std::optional<CameraIntrinsicsInfo>& right) {
  math::LaserCameraCalibration own;
  std::string error;
  if (!right || !WithRobotIntrinsics(shared, *right, &own, &error)) return shared;
  return own;
}

IntrinsicsAdopter::Result IntrinsicsAdopter::Apply(
    const std::optional<CameraIntrinsicsInfo>& intrinsics,
    math::LaserCameraCalibration* calibration) {
  Result result;
  if (!intrinsics || (applied_ && SameIntrinsics(*applied_, *intrinsics))) return result;
  applied_ = intrinsics;
  if (WithRobotIntrinsics(*calibration, *intrinsics, calibration, &result.message)) {
    result.outcome = Outcome::kAdopted;
  } else {
    result.outcome = Outcome::kRefused;
  }
  return result;
}

}  // namespace mostar::ui
