// Ground truth the simulator knows exactly and the client's algorithms are scored against.
//
// LaserCameraCalibration is the true laser-camera model of the simulated robot, in the terms
// of the MOSTAR laser-camera model (focal length in pixels, camera position relative to the
// laser, downward tilt, no pan or roll) plus what a real camera adds (principal point, radial
// distortion, per-eye offset). Positions are in the laser frame (REP-103: x forward, y left,
// z up; metres). Camera frame = OpenCV (x right, y down, z forward; pixel (0, 0) is the centre
// of the top-left pixel). The projection below is written from these definitions alone, on
// purpose independent of common/math, so each can be tested against the other.
#pragma once

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "common/types/odometry.h"
#include "common/types/stereo_frame.h"

namespace mostar::sim {

struct LaserCameraCalibration {
  int width_px = 640;
  int height_px = 480;
  double focal_px = 440;
  double cx_px = 319.5;        // principal point, both eyes
  double cy_px = 239.5;        // left eye
  double right_cy_px = 239.5;  // right eye (differs by the vertical misalignment)
  // Right eye only: rotation about its optical axis, positive = rolled clockwise seen from
  // behind (the image content turns counter-clockwise), as common/math's roll_rad.
  double right_roll_rad = 0.0;
  double k1 = 0, k2 = 0;      // radial distortion: x_d = x (1 + k1 r^2 + k2 r^4)
  double camera_x_m = -0.20;  // centre of the stereo pair, laser frame
  double camera_y_m = 0.0;
  double camera_z_m = 0.60;
  double tilt_rad = 0.21;    // rotation about the camera x axis; positive looks down
  double baseline_m = 0.12;  // left eye at camera_y_m + baseline/2, right eye at - baseline/2

  double EyeYm(Eye eye) const { return camera_y_m + (eye == Eye::kLeft ? 0.5 : -0.5) * baseline_m; }
  double Cy(Eye eye) const { return eye == Eye::kLeft ? cy_px : right_cy_px; }
  double Roll(Eye eye) const { return eye == Eye::kLeft ? 0.0 : right_roll_rad; }
  // camera_from_laser as a row-major 3x4 matrix [R | t]: p_camera = R p_laser + t.
  std::array<double, 12> CameraFromLaser(Eye eye) const;
};

// Projects a laser-frame point into an eye's image (with distortion). False when the point is
// behind the camera (z_camera <= 1 mm); u, v may fall outside the image.
bool ProjectLaserPoint(const LaserCameraCalibration& calibration, Eye eye, double x_m, double y_m,
                       double z_m, double* u_px, double* v_px);

// Pixel labels of a rendered image.
enum Label : uint8_t {
  kLabelFloor = 0,  // 1..253: obstacle id (World obstacle index + 1, clamped to 253)
  kLabelCeiling = 254,
  kLabelVoid = 255,  // beyond the floor, or nothing
};

struct ImageGroundTruth {
  cv::Mat labels;  // CV_8U, one Label per pixel
  // Per column: the row of the obstacle pixel that sits directly on a floor pixel, nearest to
  // the image bottom (the base line of the nearest obstacle, what edge discovery looks for);
  // -1 when the column has none. base_obstacle_id gives that obstacle's id (0 = none).
  std::vector<int> base_row_px;
  std::vector<int> base_obstacle_id;
  bool artifact_present = false;
  cv::Rect artifact_box;  // pixels touched by the one-eye artefact
};

// Fills base_row_px / base_obstacle_id from labels.
void ComputeBaseRows(ImageGroundTruth* truth);

// Every obstacle pixel directly above a floor pixel (all base lines, not only the nearest).
std::vector<cv::Point> BaseLinePixels(const cv::Mat& labels);

struct LaserGroundTruth {
  Pose2D world_from_base;            // pose the scan was taken at
  std::vector<float> true_ranges_m;  // noise-free, per beam (see TrueRangesAt)
};

}  // namespace mostar::sim
