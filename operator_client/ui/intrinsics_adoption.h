// Adoption of the camera intrinsics the robot publishes (CameraIntrinsicsInfo: focal lengths,
// principal point, distortion, in pixels of the robot's images) into the console's
// laser-camera calibration, whose extrinsics (and laser height, baseline) stay as they are.
// Pure.
#pragma once

#include <optional>
#include <string>

#include "common/math/camera_model.h"
#include "common/types/stereo_frame.h"

namespace mostar::ui {

// `calibration` with the intrinsics `k`, scaled into the calibration's image size when `k` is
// for another size of the same aspect ratio; false with a message (and `out` untouched) when
// `k` is for another aspect ratio or gives an invalid calibration. Missing distortion
// coefficients count as zero.
bool WithRobotIntrinsics(const math::LaserCameraCalibration& calibration,
                         const CameraIntrinsicsInfo& k, math::LaserCameraCalibration* out,
                         std::string* error);

// The right eye's calibration with per-eye intrinsics: `shared` with the right camera's own
// intrinsics when the robot publishes valid ones for this image size, else `shared`.
math::LaserCameraCalibration RightEyeCalibration(const math::LaserCameraCalibration& shared,
                                                 const std::optional<CameraIntrinsicsInfo>& right);

// Applies each new set of intrinsics once: a set equal (focal lengths, principal point,
// distortion) to the last one seen is not looked at again, refused or not.
class IntrinsicsAdopter {
 public:
  enum class Outcome {
    kNothingNew,  // no intrinsics, or the same as last time
    kAdopted,     // `calibration` now uses them
    kRefused,     // `message` says why; `calibration` unchanged
  };
  struct Result {
    Outcome outcome = Outcome::kNothingNew;
    // Refused: why (for the status line); adopted: what is used now (for the log).
    std::string message;
  };

  Result Apply(const std::optional<CameraIntrinsicsInfo>& intrinsics,
               math::LaserCameraCalibration* calibration);

 private:
  std::optional<CameraIntrinsicsInfo> applied_;
};

}  // namespace mostar::ui
