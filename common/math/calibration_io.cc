#include "common/math/calibration_io.h"

#include <cmath>

#include "common/config/config_loader.h"

namespace mostar::math {

proto::LaserCameraCalibration ToProto(const LaserCameraCalibration& calibration,
                                      const std::string& name) {
  proto::LaserCameraCalibration message;
  if (!name.empty()) message.set_name(name);
  message.set_image_width_px(calibration.image_width_px);
  message.set_image_height_px(calibration.image_height_px);
  message.set_focal_px(calibration.focal_px);
  if (calibration.focal_y_px.has_value()) message.set_focal_y_px(*calibration.focal_y_px);
  if (calibration.principal_x_px.has_value()) {
    message.set_principal_x_px(*calibration.principal_x_px);
  }
  if (calibration.principal_y_px.has_value()) {
    message.set_principal_y_px(*calibration.principal_y_px);
  }
  proto::DistortionCoefficients* distortion = message.mutable_distortion();
  distortion->set_k1(calibration.distortion.k1);
  distortion->set_k2(calibration.distortion.k2);
  distortion->set_p1(calibration.distortion.p1);
  distortion->set_p2(calibration.distortion.p2);
  distortion->set_k3(calibration.distortion.k3);
  message.set_camera_x_m(calibration.camera_x_m);
  message.set_camera_y_m(calibration.camera_y_m);
  message.set_camera_z_m(calibration.camera_z_m);
  message.set_tilt_rad(calibration.tilt_rad);
  message.set_pan_rad(calibration.pan_rad);
  message.set_roll_rad(calibration.roll_rad);
  message.set_left_eye_x_offset_m(calibration.left_eye_x_offset_m);
  message.set_right_eye_x_offset_m(calibration.right_eye_x_offset_m);
  message.set_laser_height_m(calibration.laser_height_m);
  return message;
}

bool FromProto(const proto::LaserCameraCalibration& message, LaserCameraCalibration* calibration,
               std::string* error) {
  if (!ValidateRanges(message, "calibration", error)) return false;
  LaserCameraCalibration result;
  result.image_width_px = message.image_width_px();
  result.image_height_px = message.image_height_px();
  result.focal_px = message.focal_px();
  if (message.has_focal_y_px()) result.focal_y_px = message.focal_y_px();
  if (message.has_principal_x_px()) result.principal_x_px = message.principal_x_px();
  if (message.has_principal_y_px()) result.principal_y_px = message.principal_y_px();
  result.distortion.k1 = message.distortion().k1();
  result.distortion.k2 = message.distortion().k2();
  result.distortion.p1 = message.distortion().p1();
  result.distortion.p2 = message.distortion().p2();
  result.distortion.k3 = message.distortion().k3();
  result.camera_x_m = message.camera_x_m();
  result.camera_y_m = message.camera_y_m();
  result.camera_z_m = message.camera_z_m();
  result.tilt_rad = message.tilt_rad();
  result.pan_rad = message.pan_rad();
  result.roll_rad = message.roll_rad();
  result.left_eye_x_offset_m = message.left_eye_x_offset_m();
  result.right_eye_x_offset_m = message.right_eye_x_offset_m();
  result.laser_height_m = message.laser_height_m();
  std::string reason;
  if (!result.IsValid(&reason)) {
    if (error != nullptr) *error = "calibration: " + reason;
    return false;
  }
  *calibration = result;
  return true;
}

bool LoadCalibrationProfile(const std::string& path, LaserCameraCalibration* calibration,
                            std::string* error) {
  proto::LaserCameraCalibration message;
  if (!LoadTextConfig(path, &message, error)) return false;
  std::string reason;
  if (!FromProto(message, calibration, &reason)) {
    if (error != nullptr) *error = path + ": " + reason;
    return false;
  }
  return true;
}

bool SaveCalibrationProfile(const std::string& path, const LaserCameraCalibration& calibration,
                            const std::string& name, std::string* error) {
  std::string reason;
  if (!calibration.IsValid(&reason)) {
    if (error != nullptr) *error = path + ": refusing to save an invalid calibration: " + reason;
    return false;
  }
  return SaveTextConfig(path, ToProto(calibration, name), error);
}

bool StereoAlignmentProfile::operator==(const StereoAlignmentProfile& other) const {
  return per_eye_intrinsics == other.per_eye_intrinsics &&
         right_offset_x_px == other.right_offset_x_px &&
         right_offset_y_px == other.right_offset_y_px && crop_left_px == other.crop_left_px &&
         crop_right_px == other.crop_right_px && crop_top_px == other.crop_top_px &&
         crop_bottom_px == other.crop_bottom_px && right_rotation_rad == other.right_rotation_rad;
}

proto::StereoAlignment ToProto(const StereoAlignmentProfile& alignment) {
  proto::StereoAlignment message;
  message.set_model(alignment.per_eye_intrinsics ? proto::StereoAlignment::PER_EYE_INTRINSICS
                                                 : proto::StereoAlignment::SHARED);
  message.set_right_offset_x_px(alignment.right_offset_x_px);
  message.set_right_offset_y_px(alignment.right_offset_y_px);
  message.set_crop_left_px(alignment.crop_left_px);
  message.set_crop_right_px(alignment.crop_right_px);
  message.set_crop_top_px(alignment.crop_top_px);
  message.set_crop_bottom_px(alignment.crop_bottom_px);
  message.set_right_rotation_deg(alignment.right_rotation_rad * 180.0 / M_PI);
  return message;
}

StereoAlignmentProfile FromProto(const proto::StereoAlignment& message) {
  StereoAlignmentProfile alignment;
  alignment.per_eye_intrinsics = message.model() == proto::StereoAlignment::PER_EYE_INTRINSICS;
  alignment.right_offset_x_px = message.right_offset_x_px();
  alignment.right_offset_y_px = message.right_offset_y_px();
  alignment.crop_left_px = message.crop_left_px();
  alignment.crop_right_px = message.crop_right_px();
  alignment.crop_top_px = message.crop_top_px();
  alignment.crop_bottom_px = message.crop_bottom_px();
  alignment.right_rotation_rad = message.right_rotation_deg() * M_PI / 180.0;
  return alignment;
}

bool LoadCalibrationProfile(const std::string& path, LaserCameraCalibration* calibration,
                            StereoAlignmentProfile* alignment, std::string* error) {
  proto::LaserCameraCalibration message;
  if (!LoadTextConfig(path, &message, error)) return false;
  LaserCameraCalibration loaded;
  std::string reason;
  if (!FromProto(message, &loaded, &reason)) {
    if (error != nullptr) *error = path + ": " + reason;
    return false;
  }
  *calibration = loaded;
  *alignment = FromProto(message.stereo_alignment());
  return true;
}

bool SaveCalibrationProfile(const std::string& path, const LaserCameraCalibration& calibration,
                            const StereoAlignmentProfile& alignment, const std::string& name,
                            std::string* error) {
  std::string reason;
  if (!calibration.IsValid(&reason)) {
    if (error != nullptr) *error = path + ": refusing to save an invalid calibration: " + reason;
    return false;
  }
  proto::LaserCameraCalibration message = ToProto(calibration, name);
  *message.mutable_stereo_alignment() = ToProto(alignment);
  return SaveTextConfig(path, message, error);
}

}  // namespace mostar::math
