// The scan drawn on an image at the image's capture time (issue 17, thesis 9): its beams moved
// with the odometry between the scan and the image (fusion/motion_compensation.h), or, when no
// odometry covers that gap, drawn as measured and faded so that the operator sees it is off.
// Pure: no GL.
#pragma once

#include <string>

#include "operator_client/fusion/ar_features.h"
#include "operator_client/fusion/motion_compensation.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::ui {

struct MotionOverlayOptions {
  bool enabled = true;  // client config ar.motion_compensation; off: the thesis' drawing
  fusion::MotionCompensationOptions compensation;
  // Alpha factor of a scan that could not be moved to the image's time. In (0, 1].
  float faded_alpha_scale = 0.35f;

  bool IsValid(std::string* error) const;
};

// What the overlay of the frame drawn is, for the HUD.
struct MotionOverlayStatus {
  bool moved = false;      // the scan sits at the image's time
  bool faded = false;      // compensation on, an image to register to, and the scan not moved
  double scan_age_ms = 0;  // image stamp minus scan stamp (0 without an image)
  std::string reason;      // why faded
};

// The features of `scan` for the frame: with `moved` (the scan moved to the image's time; null
// when compensation is off or there is no image) and moved->moved, the beams are drawn where it
// puts them; with `moved` but not moved->moved, as measured and faded. Without `moved`, as
// measured, not faded.
MotionOverlayStatus BuildOverlayFeatures(const fusion::ArFeatureBuilder& builder,
                                         const LaserScan& scan, const fusion::MovedScan* moved,
                                         const MotionOverlayOptions& options,
                                         fusion::ArFeatures* features);

// The scan handed to edge processing with a pair (issue 36): `nearest` (the scan nearest the
// pair's capture time) moved to that time and resampled on its beam grid
// (fusion::ResampleAtImageTime) when `moved` (MoveScanToImageTime's output for it; null when
// compensation is off) could move it; else `nearest` as measured. Edge processing then walks its
// virtual rays, compares NEPs with the laser and pairs points for the self-calibration from the
// camera's pose, and its corrected scan is drawn as it is (BuildPlacedOverlayFeatures): moved
// once.
vision::ScanPlacement PlaceScanForVision(const LaserScan& nearest, const fusion::MovedScan* moved,
                                         LaserScan* out);

// The features of a scan edge processing placed (a result's corrected scan, `placement` from its
// result) over the image captured at `image_stamp`, never moved again: where it is when
// placement.at_image_time; else as measured, faded when `compensate` (compensation on) with
// placement.reason. Without `compensate`, as measured and not faded (the thesis' drawing).
MotionOverlayStatus BuildPlacedOverlayFeatures(const fusion::ArFeatureBuilder& builder,
                                               const LaserScan& scan,
                                               const vision::ScanPlacement& placement,
                                               Time image_stamp, bool compensate,
                                               const MotionOverlayOptions& options,
                                               fusion::ArFeatures* features);

// Multiplies the alpha of what the scan placed (walls, rays, vertical lines, laser points and
// the labels' colours) by `scale`; the distance circles stay: they go with the robot.
void FadeScanFeatures(float scale, fusion::ArFeatures* features);

// The HUD line for `status`: empty unless faded.
std::string MotionOverlayNote(const MotionOverlayStatus& status);

}  // namespace mostar::ui
