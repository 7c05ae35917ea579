#include "operator_client/render/eye_geometry.h"

#include <cmath>

namespace mostar::render {

bool EyeAlignment::operator==(const EyeAlignment& other) const {
  return offset_x_px == other.offset_x_px && offset_y_px == other.offset_y_px &&
         rotation_rad == other.rotation_rad && crop_left_px == other.crop_left_px &&
         crop_right_px == other.crop_right_px && crop_top_px == other.crop_top_px &&
         crop_bottom_px == other.crop_bottom_px;
}

void CropForRightOffset(float dx_px, float dy_px, EyeAlignment* left, EyeAlignment* right) {
  left->offset_x_px = 0.f;
  left->offset_y_px = 0.f;
  right->offset_x_px = dx_px;
  right->offset_y_px = dy_px;
  for (EyeAlignment* a : {left, right}) {
    a->crop_left_px = dx_px > 0 ? dx_px : 0;
    a->crop_right_px = dx_px < 0 ? -dx_px : 0;
    a->crop_top_px = dy_px > 0 ? dy_px : 0;
    a->crop_bottom_px = dy_px < 0 ? -dy_px : 0;
  }
}

const char* AlignmentModelName(AlignmentModel model) {
  switch (model) {
    case AlignmentModel::kSharedModel:
      return "shared";
    case AlignmentModel::kPerEyeIntrinsics:
      return "per_eye";
  }
  return "?";
}

std::optional<EyeGeometry> MakeEyeGeometry(const math::LaserCameraCalibration& calibration,
                                           math::Eye eye, const EyeAlignment& alignment,
                                           AlignmentModel model, std::string* error) {
  if (!calibration.IsValid(error)) return std::nullopt;
  // The principal point and roll of the other model: moved by the offset and the rotation one
  // way or the other.
  const double sign = model == AlignmentModel::kSharedModel ? -1.0 : 1.0;
  math::LaserCameraCalibration moved = calibration;
  moved.principal_x_px = calibration.cx() + sign * alignment.offset_x_px;
  moved.principal_y_px = calibration.cy() + sign * alignment.offset_y_px;
  moved.roll_rad = calibration.roll_rad + sign * alignment.rotation_rad;
  std::string why;
  std::optional<math::CameraModel> other = math::CameraModel::Create(moved, eye, &why);
  if (!other) {
    if (error != nullptr) *error = "stereo alignment: " + why;
    return std::nullopt;
  }
  const math::CameraModel given(calibration, eye);
  if (model == AlignmentModel::kSharedModel) return EyeGeometry{*other, given};
  return EyeGeometry{given, *other};
}

ImageWarp MakeImageWarp(const EyeGeometry& geometry) {
  const math::LaserCameraCalibration& image = geometry.image.calibration();
  const math::LaserCameraCalibration& display = geometry.display.calibration();
  ImageWarp warp;
  warp.fx = static_cast<float>(image.fx());
  warp.fy = static_cast<float>(image.fy());
  warp.rotation_cos = static_cast<float>(std::cos(display.roll_rad - image.roll_rad));
  warp.rotation_sin = static_cast<float>(std::sin(display.roll_rad - image.roll_rad));
  warp.display_cx = static_cast<float>(display.cx());
  warp.display_cy = static_cast<float>(display.cy());
  warp.image_cx = static_cast<float>(image.cx());
  warp.image_cy = static_cast<float>(image.cy());
  warp.k1 = static_cast<float>(image.distortion.k1);
  warp.k2 = static_cast<float>(image.distortion.k2);
  warp.p1 = static_cast<float>(image.distortion.p1);
  warp.p2 = static_cast<float>(image.distortion.p2);
  warp.k3 = static_cast<float>(image.distortion.k3);
  return warp;
}

Eigen::Vector2d WarpToImage(const ImageWarp& w, const Eigen::Vector2d& display_px) {
  const double xr = (display_px.x() - w.display_cx) / w.fx;
  const double yr = (display_px.y() - w.display_cy) / w.fy;
  const double x = w.rotation_cos * xr - w.rotation_sin * yr;
  const double y = w.rotation_sin * xr + w.rotation_cos * yr;
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (w.k1 + r2 * (w.k2 + r2 * w.k3));
  const double xd = x * radial + 2.0 * w.p1 * x * y + w.p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + w.p1 * (r2 + 2.0 * y * y) + 2.0 * w.p2 * x * y;
  return Eigen::Vector2d(w.image_cx + w.fx * xd, w.image_cy + w.fy * yd);
}

float SuggestedRightOffsetY(const EyeGeometry& left, const EyeGeometry& right,
                            const EyeAlignment& left_alignment, double residual_px) {
  // Displayed row = camera-image row + offset in each eye; the right camera's content sits
  // residual_px below where its image model expects it.
  const double left_cy = left.image.calibration().cy();
  const double right_cy = right.image.calibration().cy();
  return static_cast<float>(left_alignment.offset_y_px + left_cy - right_cy - residual_px);
}

math::StereoAlignmentProfile ToProfile(AlignmentModel model, const EyeAlignment& left,
                                       const EyeAlignment& right) {
  math::StereoAlignmentProfile p;
  p.per_eye_intrinsics = model == AlignmentModel::kPerEyeIntrinsics;
  p.right_offset_x_px = right.offset_x_px - left.offset_x_px;
  p.right_offset_y_px = right.offset_y_px - left.offset_y_px;
  p.crop_left_px = right.crop_left_px;
  p.crop_right_px = right.crop_right_px;
  p.crop_top_px = right.crop_top_px;
  p.crop_bottom_px = right.crop_bottom_px;
  p.right_rotation_rad = right.rotation_rad - left.rotation_rad;
  return p;
}

void FromProfile(const math::StereoAlignmentProfile& p, AlignmentModel* model, EyeAlignment* left,
                 EyeAlignment* right) {
  *model = p.per_eye_intrinsics ? AlignmentModel::kPerEyeIntrinsics : AlignmentModel::kSharedModel;
  *left = EyeAlignment{};
  *right = EyeAlignment{};
  right->offset_x_px = static_cast<float>(p.right_offset_x_px);
  right->offset_y_px = static_cast<float>(p.right_offset_y_px);
  right->rotation_rad = static_cast<float>(p.right_rotation_rad);
  for (EyeAlignment* a : {left, right}) {
    a->crop_left_px = static_cast<float>(p.crop_left_px);
    a->crop_right_px = static_cast<float>(p.crop_right_px);
    a->crop_top_px = static_cast<float>(p.crop_top_px);
    a->crop_bottom_px = static_cast<float>(p.crop_bottom_px);
  }
}

bool StereoGeometry::Update(const math::LaserCameraCalibration& left,
                            const math::LaserCameraCalibration& right, AlignmentModel model,
                            const EyeAlignment& left_alignment, const EyeAlignment& right_alignment,
                            std::string* error) {
  error->clear();
  const math::LaserCameraCalibration* calibrations[2] = {&left, &right};
  const EyeAlignment* alignments[2] = {&left_alignment, &right_alignment};
  std::string key = math::ToProto(left).SerializeAsString() + "|" +
                    math::ToProto(right).SerializeAsString() + "|" + AlignmentModelName(model);
  for (const EyeAlignment* a : alignments) {
    key += "|" + std::to_string(a->offset_x_px) + "," + std::to_string(a->offset_y_px) + "," +
           std::to_string(a->rotation_rad);
  }
  if (key == key_ && ready()) return false;
  std::optional<EyeGeometry> next[2];
  for (int e = 0; e < 2; ++e) {
    const math::Eye eye = e == 0 ? math::Eye::kLeft : math::Eye::kRight;
    std::string why;
    next[e] = MakeEyeGeometry(*calibrations[e], eye, *alignments[e], model, &why);
    if (next[e]) continue;
    *error = why;
    if (ready()) return false;  // keep the previous geometry
    next[e] = MakeEyeGeometry(*calibrations[e], eye, {}, model, &why);
    if (!next[e]) {
      *error = why;
      return false;
    }
  }
  key_ = key;
  eyes_[0] = next[0];
  eyes_[1] = next[1];
  return true;
}

bool LoadAlignment(const std::string& path, AlignmentModel* model, EyeAlignment* left,
                   EyeAlignment* right, std::string* error) {
  math::LaserCameraCalibration calibration;
  math::StereoAlignmentProfile alignment;
  if (!math::LoadCalibrationProfile(path, &calibration, &alignment, error)) return false;
  FromProfile(alignment, model, left, right);
  return true;
}

}  // namespace mostar::render
