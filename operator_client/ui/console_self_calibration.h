// The self-refining calibration in the console (issue 17): the shown edge results' agreeing
// NEPs fill a rolling window of correspondences (calibration/edge_correspondences.h); at a low
// rate the window goes to a fit worker (calibration/fit_worker.h) with the eyes' image
// calibrations; the calibration panel shows the newest proposal and the operator applies or
// rejects it. Nothing is ever applied without Apply().
//
// Render thread only; never waits for the fit. No GL, no ImGui.
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "operator_client/calibration/edge_correspondences.h"
#include "operator_client/calibration/fit_worker.h"
#include "operator_client/render/eye_geometry.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::ui {

class ConsoleSelfCalibration {
 public:
  struct Options {
    bool enabled = true;                             // off: Update does nothing
    size_t window_points = 3000;                     // newest correspondences kept
    Duration window_age = std::chrono::seconds(60);  // and none older than this
    Duration fit_period = std::chrono::seconds(2);   // of image time between fits
    // A result is added only with another scan than the last one added (one scan serves about
    // three images) and, when odometry is known, once the robot has moved this far (m) or
    // turned this much (rad) since: a still robot repeats its evidence, which would make a
    // proposal look surer than it is. Both 0: every result with a new scan.
    double min_motion_m = 0.02;
    double min_turn_rad = 0.5 * M_PI / 180.0;
    calibration::CorrespondenceOptions correspondences;
    calibration::FitOptions fit;

    bool IsValid(std::string* error) const;
  };

  ConsoleSelfCalibration() : ConsoleSelfCalibration(Options{}) {}
  // The options must be valid (checked).
  explicit ConsoleSelfCalibration(const Options& options);

  bool enabled() const { return options_.enabled; }
  // One render tick with the shown edge result (null: none yet) and the robot's newest odometry
  // (nullopt: none); nothing when disabled. A result not seen before adds
  // its correspondences, with the scan it was computed against (VisionResult::scan: at the
  // image's time when the console could move it there, so laser points and edge pixels are
  // paired from one camera pose);
  // every fit_period of image time the window is handed to the fit worker with `geometry`'s
  // image calibrations. An image size change empties the window.
  void Update(const std::shared_ptr<const vision::VisionResult>& result,
              const std::optional<Odometry>& odometry, const vision::VisionOptions& vision,
              const render::StereoGeometry& geometry);

  // The proposal to show: the newest fit, unless rejected or computed from a calibration that
  // is no longer in force (after Apply or a slider edit). Null when there is none.
  std::shared_ptr<const calibration::FitResult> proposal() const;
  // proposal() is there and can be applied.
  bool trustworthy_proposal() const;
  size_t window_points() const { return window_.size(); }
  // Results not added: their scan was already added, or the robot had not moved.
  uint64_t repeated_results() const { return repeated_results_; }

  // Moves `live` (the profile) by what the proposal changes (calibration::MoveParameters: the
  // fit ran on the image models, which may be scaled) and hides the proposal. Refused, with
  // `message` saying why, when there is no trustworthy proposal.
  bool Apply(math::LaserCameraCalibration* live, std::string* message);
  // Hides the proposal until the next fit.
  void Reject();

 private:
  Options options_;
  calibration::CorrespondenceWindow window_;
  calibration::FitWorker worker_;
  uint64_t last_sequence_ = 0;
  bool seen_any_ = false;
  std::optional<Time> last_fit_stamp_;
  std::optional<Time> last_added_scan_;    // measured stamp of the scan of the last result added
  std::optional<Pose2D> last_added_pose_;  // the odometry then
  uint64_t repeated_results_ = 0;
  int width_px_ = 0;
  int height_px_ = 0;
  calibration::ParameterVector in_force_{};  // the left image calibration now
  std::shared_ptr<const calibration::FitResult> rejected_;
};

}  // namespace mostar::ui
