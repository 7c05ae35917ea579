// 2D-3D correspondences for refining the laser-camera calibration from the images themselves
// (issue 17, "Calibration that refines itself"; beyond thesis 7.3).
//
// A beam whose nearest edge point (NEP) agrees with its laser point (thesis 8.3) shows the base
// of the object the laser hit: the floor point under the laser point lies on the image edge the
// NEP was found on. The NEP itself lies where the (possibly miscalibrated) virtual ray crossed
// that edge, so only its distance ACROSS the edge is evidence; its position along the edge
// repeats the calibration in force. A correspondence therefore carries the 3D base line (the
// floor point under the laser point and the wall's direction from the neighbouring laser points)
// and the NEP pixel; the fit (calibration_fit.h) minimises the pixel distance from the NEP to
// the projected base line.
//
// Frames: laser frame (common/math/camera_model.h); the floor is z = -laser_height_m. Pixels of
// the image model of the eye that found the NEP.
//
// Pure functions and a plain container: no threads, no OpenGL, no DDS.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <deque>
#include <string>
#include <vector>

#include "common/math/camera_model.h"
#include "common/time/time.h"
#include "common/types/laser_scan.h"
#include "operator_client/vision/vision_pipeline.h"

namespace mostar::calibration {

struct EdgeCorrespondence {
  Eye eye = Eye::kLeft;  // whose image the pixel is in
  // The floor point under the laser point, moved onto the base line fitted to its neighbours.
  Eigen::Vector3d base_laser = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction_laser = Eigen::Vector3d::UnitY();  // unit, horizontal: the base line
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();             // the NEP (edge pixel)
  Time stamp;                                                  // capture time of the image
};

struct CorrespondenceOptions {
  // Beams on each side whose laser points must lie on one straight base line with the beam's
  // own (corners, clutter and thin objects give no line); in [1, 10].
  int line_half_beams = 3;
  // Largest distance of those laser points from their fitted line, metres; > 0.
  double max_line_residual_m = 0.015;
  // Smallest angle between the base line and the beam, radians: a line seen end-on fixes no
  // direction across it; in [0, pi/2).
  double min_incidence_rad = 20.0 * M_PI / 180.0;
  // Laser ranges used, metres: near enough for the floor distance to be well resolved.
  double max_range_m = 6.0;

  bool IsValid(std::string* error) const;
};

// The correspondences of one processed frame pair: for each beam the classifier marked kAgrees
// and each eye whose own NEP (VisionResult::left_ned / right_ned) agrees with the beam's laser
// range under `classifier`, the beam's base line and that eye's NEP pixel. `scan` is the scan
// the pipeline processed (same beam count as the result), `laser_height_m` the calibration's.
// A result that is not ok, or sizes that do not match, give none.
std::vector<EdgeCorrespondence> ExtractCorrespondences(
    const vision::VisionResult& result, const LaserScan& scan,
    const vision::NepClassifierOptions& classifier, double laser_height_m,
    const CorrespondenceOptions& options);

// A rolling window of correspondences: the newest `capacity`, none older than `max_age` behind
// the newest stamp added. Single-threaded.
class CorrespondenceWindow {
 public:
  CorrespondenceWindow(size_t capacity, Duration max_age);

  void Add(const std::vector<EdgeCorrespondence>& correspondences);
  void Clear() { items_.clear(); }
  size_t size() const { return items_.size(); }
  std::vector<EdgeCorrespondence> Snapshot() const;

 private:
  size_t capacity_;
  Duration max_age_;
  std::deque<EdgeCorrespondence> items_;  // in the order added
};

}  // namespace mostar::calibration
