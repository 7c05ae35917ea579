// The decoded images' pixels against the calibration's. The calibration profile (intrinsics,
// stereo alignment offsets and crops) is in the pixels of its own image size; the receiver
// decodes at the size the window shows (DCT scaling, 1/2 .. 1/8) and a robot on its bitrate
// ladder sends smaller images. Everything drawn over an image and every vision step uses the
// calibration scaled to that image's size, so the overlay stays registered. Pure.
#pragma once

#include <optional>
#include <utility>

#include "common/math/camera_model.h"
#include "common/types/stereo_frame.h"
#include "operator_client/render/display_mode.h"
#include "operator_client/render/eye_geometry.h"
#include "operator_client/video/stereo_receiver.h"

namespace mostar::ui {

// Decoded image pixels per calibration pixel, and the decoded size.
struct ImageScale {
  int width_px = 0;  // 0: no image yet (scale 1)
  int height_px = 0;
  double x = 1.0;
  double y = 1.0;
  bool operator==(const ImageScale& o) const {
    return width_px == o.width_px && height_px == o.height_px;
  }
};

// The scale of the images of `pair` against `calibration`; `previous` when there is no pair or
// it has no image.
ImageScale ScaleOfPair(const math::LaserCameraCalibration& calibration,
                       const std::optional<client::DecodedStereoPair>& pair,
                       const ImageScale& previous);

// `calibration` in the pixels of an image of scale.width_px x scale.height_px: focal lengths
// times the scale, the principal point with pixel centres kept (c' + 0.5 = (c + 0.5) * s).
// Distortion (normalised coordinates) and extrinsics do not change. No image: unchanged.
math::LaserCameraCalibration ScaledCalibration(const math::LaserCameraCalibration& calibration,
                                               const ImageScale& scale);

// Offsets and crops times the scale.
render::EyeAlignment ScaledAlignment(const render::EyeAlignment& alignment,
                                     const ImageScale& scale);

// Both eyes' calibrations in the decoded images' pixels: `shared` for the left eye; for the
// right eye `right_own` (with per-eye intrinsics: the right camera's published intrinsics) when
// valid for this profile (RightEyeCalibration), else `shared`.
std::pair<math::LaserCameraCalibration, math::LaserCameraCalibration> ScaledEyeCalibrations(
    const math::LaserCameraCalibration& shared,
    const std::optional<CameraIntrinsicsInfo>& right_own, const ImageScale& scale);

// NESC's residual (px of the decoded images) as the right eye's vertical offset in the profile's
// pixels (render::SuggestedRightOffsetY with `geometry` and the scaled left alignment).
float SuggestedRightOffsetInProfile(const render::StereoGeometry& geometry,
                                    const render::EyeAlignment& left_alignment,
                                    const ImageScale& scale, double residual_px);

// What to decode for `mode` in a framebuffer of fb_w x fb_h: the eyes shown, plus the eyes edge
// processing needs when it is on (both for NESC, the left for monoscopic processing), at the
// size of the largest eye viewport.
client::DecodeTarget DecodeTargetFor(render::DisplayMode mode, int fb_w, int fb_h,
                                     bool vision_enabled, bool vision_stereo);

}  // namespace mostar::ui
