#include "operator_client/ui/intrinsics_adoption.h"

#include <cstdint>
#include <sstream>

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
  // Another size of the same aspect ratio (the native 1280x960 against a 640x480 profile, a
  // rung of the robot's bitrate ladder): the intrinsics are scaled into the profile's pixels,
  // pixel centres kept (c' + 0.5 = (c + 0.5) * s).
  if (k.width_px <= 0 || k.height_px <= 0 ||
      static_cast<int64_t>(k.width_px) * calibration.image_height_px !=
          static_cast<int64_t>(k.height_px) * calibration.image_width_px) {
    *error = "robot intrinsics are for " + std::to_string(k.width_px) + "x" +
             std::to_string(k.height_px) + " images, not of the aspect ratio of " +
             std::to_string(calibration.image_width_px) + "x" +
             std::to_string(calibration.image_height_px) + ": not used";
    return false;
  }
  const double sx = static_cast<double>(calibration.image_width_px) / k.width_px;
  const double sy = static_cast<double>(calibration.image_height_px) / k.height_px;
  math::LaserCameraCalibration next = calibration;
  next.focal_px = k.fx * sx;
  next.focal_y_px = k.fy * sy;
  next.principal_x_px = (k.cx + 0.5) * sx - 0.5;
  next.principal_y_px = (k.cy + 0.5) * sy - 0.5;
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
    const CameraIntrinsicsInfo& k = *intrinsics;
    std::ostringstream message;
    message << "using the robot's camera intrinsics: f " << k.fx << "/" << k.fy
            << " px, principal point (" << k.cx << ", " << k.cy << ") for " << k.width_px << "x"
            << k.height_px << " images";
    result.message = message.str();
  } else {
    result.outcome = Outcome::kRefused;
  }
  return result;
}

}  // namespace mostar::ui
