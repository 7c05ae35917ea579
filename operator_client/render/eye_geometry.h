// One geometry per eye for everything that is drawn or measured on it: the camera image as it
// arrives (NED and NESC search edges in it) and the image as it is displayed (the overlay, the
// labels). Pure: no GL.
//
// The displayed image is the camera image undistorted (lens distortion removed, so the overlay
// is an exact pinhole drawing: straight 3D edges stay straight) and shifted by the eye's stereo
// alignment offset (thesis 9.1). A laser point p is then displayed at display.ProjectUndistorted
// (p) and its content is at image.Project(p) in the camera image; the two models differ only in
// the principal point (display = image + offset) and the roll (display = image + rotation), so
// the image shader, the overlay and NED agree by construction.
//
// Which of the two the calibration describes is the alignment model:
// - kSharedModel (thesis 9.1): focal length, y, z and tilt are shared by both eyes and only x
//   differs; the calibration describes the DISPLAYED images, which the offsets have aligned with
//   each other. The overlay is not moved by the offset; NED's model of the camera image is the
//   calibration with the principal point moved back by the offset.
// - kPerEyeIntrinsics: each eye's calibration describes its own CAMERA image (intrinsics from an
//   OpenCV calibration); the offset aligns the images for the eyes and moves the overlay with
//   its image.
#pragma once

#include <optional>
#include <string>

#include "common/math/calibration_io.h"
#include "common/math/camera_model.h"

namespace mostar::render {

// Stereo alignment of one eye (thesis 9.1): its image is shifted by (offset_x_px, offset_y_px)
// pixels (+x right, +y down) and turned by rotation_rad about its principal point, as a camera
// roll would turn it (the calibration's roll convention: a camera rolled by r is aligned with
// the other eye by -r); the borders with no correspondence in the other eye are cropped (drawn
// black), in pixels of the displayed image (corners a rotation uncovers are black too).
struct EyeAlignment {
  float offset_x_px = 0.f;
  float offset_y_px = 0.f;
  float rotation_rad = 0.f;
  float crop_left_px = 0.f;
  float crop_right_px = 0.f;
  float crop_top_px = 0.f;
  float crop_bottom_px = 0.f;

  bool operator==(const EyeAlignment& other) const;
};

// Crops both eyes so that only what both show remains, for the right eye shifted by
// (dx, dy) px relative to the left one (left offsets zero).
void CropForRightOffset(float dx_px, float dy_px, EyeAlignment* left, EyeAlignment* right);

enum class AlignmentModel {
  kSharedModel,       // the calibration describes the displayed, aligned images (thesis)
  kPerEyeIntrinsics,  // each eye's calibration describes its own camera image
};

const char* AlignmentModelName(AlignmentModel model);

struct EyeGeometry {
  math::CameraModel image;    // the camera image as received: NED, NESC, the 8.3 correction
  math::CameraModel display;  // the displayed image, distortion removed: overlay (pinhole GL
                              // matrices), labels; same as `image` but for the principal point
};

// The eye's two models. `calibration` is the eye's calibration (for kSharedModel the shared one).
// nullopt with `error` when the calibration is invalid or the offset moves a principal point out
// of the image.
std::optional<EyeGeometry> MakeEyeGeometry(const math::LaserCameraCalibration& calibration,
                                           math::Eye eye, const EyeAlignment& alignment,
                                           AlignmentModel model, std::string* error);

// Both eyes' geometry, rebuilt only when an input changes (the console asks every frame). An
// offset that moves a principal point out of the image is refused: the previous geometry stays,
// or at the first build the geometry without offsets. Pure.
class StereoGeometry {
 public:
  // True when the geometry changed. `error` gets why an eye's alignment was refused (empty when
  // none was). False with `error` and no geometry only when even the calibration without
  // offsets is invalid.
  bool Update(const math::LaserCameraCalibration& left, const math::LaserCameraCalibration& right,
              AlignmentModel model, const EyeAlignment& left_alignment,
              const EyeAlignment& right_alignment, std::string* error);
  bool ready() const { return eyes_[0].has_value() && eyes_[1].has_value(); }
  // The eye's geometry; only when ready(). 0 = left, 1 = right.
  const EyeGeometry& eye(int e) const { return *eyes_[e]; }

 private:
  std::string key_;  // the inputs of the current geometry
  std::optional<EyeGeometry> eyes_[2];
};

// What the image shader needs: for a displayed pixel q, the camera-image pixel it shows is
//   image_c + f * Distort(R (q - display_c) / f)   (per axis f = fx or fy, c = (cx, cy)),
// R the rotation by the display's roll minus the image's ([cos -sin; sin cos]); with no
// distortion and no rotation that is q - offset.
struct ImageWarp {
  float fx = 1.f, fy = 1.f;
  float rotation_cos = 1.f, rotation_sin = 0.f;
  float display_cx = 0.f, display_cy = 0.f;
  float image_cx = 0.f, image_cy = 0.f;
  float k1 = 0.f, k2 = 0.f, p1 = 0.f, p2 = 0.f, k3 = 0.f;
};

ImageWarp MakeImageWarp(const EyeGeometry& geometry);
// The camera-image pixel a displayed pixel shows (the shader's formula, in double).
Eigen::Vector2d WarpToImage(const ImageWarp& warp, const Eigen::Vector2d& display_px);

// The right eye's vertical offset that aligns the two displayed images, from NESC's residual
// (vision/nesc.h, StereoOffsetEstimate: right NEP row minus the row the right image model
// expects, camera-image pixels) measured with these geometries: the same floor point is then on
// the same displayed row in both eyes (parallel, level cameras).
float SuggestedRightOffsetY(const EyeGeometry& left, const EyeGeometry& right,
                            const EyeAlignment& left_alignment, double residual_px);

// The profile's form of the alignment (common/math/calibration_io.h) and back. The left eye's
// offset is not saved (the right one is relative to it); crops are saved for both eyes.
math::StereoAlignmentProfile ToProfile(AlignmentModel model, const EyeAlignment& left,
                                       const EyeAlignment& right);
void FromProfile(const math::StereoAlignmentProfile& profile, AlignmentModel* model,
                 EyeAlignment* left, EyeAlignment* right);
// The alignment saved in the calibration profile at `path` (no offsets when it has none);
// false with a message, and nothing changed, when the file cannot be read.
bool LoadAlignment(const std::string& path, AlignmentModel* model, EyeAlignment* left,
                   EyeAlignment* right, std::string* error);

}  // namespace mostar::render
