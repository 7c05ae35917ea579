// Pinhole intrinsics of one eye, from an OpenCV FileStorage calibration file (YAML or XML, as
// written by OpenCV's calibration sample and cv::FileStorage):
//
//   image_width: 640            # pixels
//   image_height: 480
//   camera_matrix: !!opencv-matrix {rows: 3, cols: 3, dt: d, data: [fx, 0, cx, 0, fy, cy, 0, 0, 1]}
//   distortion_coefficients: !!opencv-matrix {rows: 1, cols: 5, dt: d, data: [k1, k2, p1, p2, k3]}
//
// Units: pixels; OpenCV camera frame (x right, y down, z forward; pixel (0, 0) is the centre of
// the top-left pixel). Distortion follows OpenCV's model (4, 5, 8, 12 or 14 coefficients).
#pragma once

#include <opencv2/core/matx.hpp>
#include <opencv2/core/types.hpp>
#include <string>
#include <vector>

namespace mostar::camera {

struct CameraIntrinsics {
  cv::Size image_size;             // pixels the calibration was made at
  cv::Matx33d camera_matrix;       // K = [fx 0 cx; 0 fy cy; 0 0 1], pixels
  std::vector<double> distortion;  // OpenCV order: k1 k2 p1 p2 [k3 [k4 k5 k6 ...]]
  // fx, fy > 0, principal point inside the image, K's last row (0 0 1), a valid count of
  // distortion coefficients.
  bool IsValid(std::string* error) const;
  // The same camera at another resolution (e.g. the JPEG downscale): K scales per axis.
  CameraIntrinsics ScaledTo(cv::Size size) const;
};

// Loads `path`; false with "<path>: <reason>" in `error` on a missing, unparsable or invalid file.
bool LoadCameraIntrinsics(const std::string& path, CameraIntrinsics* intrinsics,
                          std::string* error);
// Writes in the same format (YAML when the name ends in .yaml/.yml, XML for .xml).
bool SaveCameraIntrinsics(const std::string& path, const CameraIntrinsics& intrinsics,
                          std::string* error);

}  // namespace mostar::camera
