#include "operator_client/ui/decode_scaling.h"

#include <algorithm>

#include "operator_client/render/eye_viewports.h"
#include "operator_client/ui/intrinsics_adoption.h"

namespace mostar::ui {

ImageScale ScaleOfPair(const math::LaserCameraCalibration& calibration,
                       const std::optional<client::DecodedStereoPair>& pair,
                       const ImageScale& previous) {
  if (!pair) return previous;
  const cv::Mat& image = pair->left.empty() ? pair->right : pair->left;
  if (image.empty()) return previous;
  ImageScale scale;
  scale.width_px = image.cols;
  scale.height_px = image.rows;
  scale.x = static_cast<double>(image.cols) / calibration.image_width_px;
  scale.y = static_cast<double>(image.rows) / calibration.image_height_px;
  return scale;
}

math::LaserCameraCalibration ScaledCalibration(const math::LaserCameraCalibration& calibration,
                                               const ImageScale& scale) {
  if (scale.width_px <= 0 || scale.height_px <= 0 ||
      (scale.width_px == calibration.image_width_px &&
       scale.height_px == calibration.image_height_px)) {
    return calibration;
  }
  math::LaserCameraCalibration out = calibration;
  const double sx = static_cast<double>(scale.width_px) / calibration.image_width_px;
  const double sy = static_cast<double>(scale.height_px) / calibration.image_height_px;
  out.image_width_px = scale.width_px;
  out.image_height_px = scale.height_px;
  out.focal_px = calibration.fx() * sx;
  out.focal_y_px = calibration.fy() * sy;
  out.principal_x_px = (calibration.cx() + 0.5) * sx - 0.5;
  out.principal_y_px = (calibration.cy() + 0.5) * sy - 0.5;
  return out;
}

render::EyeAlignment ScaledAlignment(const render::EyeAlignment& alignment,
                                     const ImageScale& scale) {
  render::EyeAlignment out = alignment;
  const auto sx = static_cast<float>(scale.x);
  const auto sy = static_cast<float>(scale.y);
  out.offset_x_px *= sx;
  out.offset_y_px *= sy;
  out.crop_left_px *= sx;
  out.crop_right_px *= sx;
  out.crop_top_px *= sy;
  out.crop_bottom_px *= sy;
  return out;
}

client::DecodeTarget DecodeTargetFor(render::DisplayMode mode, int fb_w, int fb_h,
                                     bool vision_enabled, bool vision_stereo) {
  client::DecodeTarget target;
  target.left = vision_enabled;
  target.right = vision_enabled && vision_stereo;
  for (const render::EyeViewport& viewport : render::EyeViewports(mode, fb_w, fb_h)) {
    (viewport.eye == math::Eye::kLeft ? target.left : target.right) = true;
    target.width_px = std::max(target.width_px, viewport.width_px);
    target.height_px = std::max(target.height_px, viewport.height_px);
  }
  return target;
}

float SuggestedRightOffsetInProfile(const render::StereoGeometry& geometry,
                                    const render::EyeAlignment& left_alignment,
                                    const ImageScale& scale, double residual_px) {
  return render::SuggestedRightOffsetY(geometry.eye(0), geometry.eye(1),
                                       ScaledAlignment(left_alignment, scale), residual_px) /
         static_cast<float>(scale.y);
}

std::pair<math::LaserCameraCalibration, math::LaserCameraCalibration> ScaledEyeCalibrations(
    const math::LaserCameraCalibration& shared,
    const std::optional<CameraIntrinsicsInfo>& right_own, const ImageScale& scale) {
  return {ScaledCalibration(shared, scale),
          ScaledCalibration(RightEyeCalibration(shared, right_own), scale)};
}

}  // namespace mostar::ui
