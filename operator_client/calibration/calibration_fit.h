// A robust least-squares refinement of the laser-camera calibration from edge correspondences
// (edge_correspondences.h): focal length, camera x, y, z, tilt, pan and roll (the parameters of
// the calibration profile, common/math/camera_model.h), started from the calibration in force.
//
// Residual: the signed pixel distance from each NEP to the image of its base line near the base
// point, the line projected with math::CameraModel::Project (distortion included; the model is
// the only projection). Loss: Huber at a coarse scale first (far from the solution every point
// pulls), then Cauchy at the fine scale (wrong correspondences lose their weight). A weak prior
// keeps parameters the points cannot see near their start. Jacobians: central differences.
//
// Work is bounded by FitOptions (points, iterations, solver time): the caller runs fits off the
// render thread. Pure: one call, no state; safe to call from any thread.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "operator_client/calibration/edge_correspondences.h"

namespace mostar::calibration {

// The refined parameters, in this order everywhere (FitResult::sigma, FitOptions::free).
enum FitParameter : int {
  kFocal = 0,  // focal_px (focal_y_px, when set, scales with it)
  kCameraX,    // camera_x_m
  kCameraY,    // camera_y_m
  kCameraZ,    // camera_z_m
  kTilt,       // tilt_rad
  kPan,        // pan_rad
  kRoll,       // roll_rad
  kParameterCount
};
using ParameterVector = std::array<double, kParameterCount>;
const char* FitParameterName(int parameter);

struct FitOptions {
  // Parameters the fit may change; the others keep their current values. By default camera x, z
  // and roll are held (measured with a ruler): on the floor edges of a corridor x trades off
  // against pan and z against f (docs/calibration.md, "Self-calibration").
  std::array<bool, kParameterCount> free = {true, false, true, false, true, true, false};
  // Huber scale of the first stage and Cauchy scale of the second, pixels; > 0.
  double coarse_loss_px = 8.0;
  double loss_px = 1.0;
  // A point fits the proposal when its residual is at most this, pixels; > 0.
  double inlier_px = 3.0;
  // Bounded work: the newest max_points correspondences; iterations per stage; solver time.
  size_t max_points = 3000;
  int max_iterations = 40;
  double max_solver_time_s = 3.0;
  // Prior standard deviations that keep unseen parameters near their start (weak).
  double prior_focal_fraction = 0.25;
  double prior_position_m = 0.25;
  double prior_angle_rad = 0.25;
  // Trustworthy only with at least this many inliers, covering this fraction of the image width
  // and height (5th to 95th percentile of the inliers' pixels), with at least this fraction of
  // points fitting, and every free parameter's standard deviation below its bound.
  size_t min_points = 80;
  double min_width_fraction = 0.3;
  double min_height_fraction = 0.06;
  double min_inlier_fraction = 0.5;
  double max_sigma_focal_fraction = 0.003;
  double max_sigma_position_m = 0.004;
  double max_sigma_angle_rad = 0.0017;  // 0.1 degree

  bool IsValid(std::string* error) const;
};

// Reprojection error (point-to-base-line distance) over the proposal's inliers, pixels.
struct ReprojectionError {
  double p50_px = 0.0;
  double p95_px = 0.0;
};

struct FitResult {
  bool ok = false;           // a proposal was computed (else `reason` says why not)
  bool trustworthy = false;  // enough points, spread, fit, well determined (else `reason`)
  std::string reason;        // empty when trustworthy
  math::LaserCameraCalibration start;     // the left base calibration the fit started from
  math::LaserCameraCalibration proposal;  // start with the refined parameters
  ReprojectionError before;               // the start calibration, over the proposal's inliers
  ReprojectionError after;                // the proposal, over its inliers
  size_t points = 0;                      // correspondences used
  size_t inliers = 0;                     // within inlier_px of the proposal
  ParameterVector sigma{};  // standard deviation of each free parameter (0 when fixed)
  int iterations = 0;       // solver iterations, both stages
};

// The base calibrations of the eyes' image models (they may differ in principal point,
// distortion and eye offset); the fitted parameters apply to both, focal length as a ratio and
// the others as offsets from the left base's values. A null right base drops right-eye points.
struct FitInput {
  math::LaserCameraCalibration left;
  std::optional<math::LaserCameraCalibration> right;
  std::vector<EdgeCorrespondence> points;
};

FitResult FitCalibration(const FitInput& input, const FitOptions& options);

// The parameters of a calibration, in FitParameter order.
ParameterVector ParametersOf(const math::LaserCameraCalibration& calibration);
// `base` moved by what the fit changed from `from` to `to`: focal length scaled by
// to/from, the other parameters offset by to - from. How a proposal computed on the image
// models is applied to the profile (the console scales the profile to the decoded images).
math::LaserCameraCalibration MoveParameters(const math::LaserCameraCalibration& base,
                                            const ParameterVector& from, const ParameterVector& to);

}  // namespace mostar::calibration
