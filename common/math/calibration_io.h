// Calibration profiles: LaserCameraCalibration <-> protobuf (common/math/calibration.proto) and
// text files (protobuf text format, e.g. deploy/config/calibration_morduc.pbtxt).
#pragma once

#include <string>

#include "common/math/calibration.pb.h"
#include "common/math/camera_model.h"

namespace mostar::math {

// Every field is written; the optional intrinsics (focal_y_px, principal point) only when set.
proto::LaserCameraCalibration ToProto(const LaserCameraCalibration& calibration,
                                      const std::string& name = "");

// Unset proto fields take the proto defaults (equal to LaserCameraCalibration's). Returns false
// and sets `error` when the declared ranges or LaserCameraCalibration::IsValid() are violated;
// `calibration` is then unchanged.
bool FromProto(const proto::LaserCameraCalibration& message, LaserCameraCalibration* calibration,
               std::string* error);

// Reads a profile file; errors name the file (and line/key for syntax and range errors).
bool LoadCalibrationProfile(const std::string& path, LaserCameraCalibration* calibration,
                            std::string* error);

// Writes a profile file atomically (for the calibration panel's "save").
bool SaveCalibrationProfile(const std::string& path, const LaserCameraCalibration& calibration,
                            const std::string& name, std::string* error);

// The stereo alignment a profile may carry beside the calibration (calibration.proto,
// StereoAlignment): pixels of the displayed images.
struct StereoAlignmentProfile {
  bool per_eye_intrinsics = false;  // false: the thesis' shared-parameter model
  double right_offset_x_px = 0.0;   // +x right
  double right_offset_y_px = 0.0;   // +y down
  double crop_left_px = 0.0;        // >= 0, both eyes
  double crop_right_px = 0.0;
  double crop_top_px = 0.0;
  double crop_bottom_px = 0.0;
  double right_rotation_rad = 0.0;  // as a camera roll; the profile holds degrees

  bool operator==(const StereoAlignmentProfile& other) const;
};

proto::StereoAlignment ToProto(const StereoAlignmentProfile& alignment);
StereoAlignmentProfile FromProto(const proto::StereoAlignment& message);

// Both from one profile file: `alignment` is the default (no shift, no crop) when the file has
// none. Nothing is changed on failure.
bool LoadCalibrationProfile(const std::string& path, LaserCameraCalibration* calibration,
                            StereoAlignmentProfile* alignment, std::string* error);
bool SaveCalibrationProfile(const std::string& path, const LaserCameraCalibration& calibration,
                            const StereoAlignmentProfile& alignment, const std::string& name,
                            std::string* error);

}  // namespace mostar::math
