#include "robot_server/camera/camera_intrinsics.h"

#include <cmath>
#include <opencv2/core.hpp>

namespace mostar::camera {

bool CameraIntrinsics::IsValid(std::string* error) const {
  if (image_size.width <= 0 || image_size.height <= 0) {
    *error = "image size must be positive";
    return false;
  }
  const cv::Matx33d& k = camera_matrix;
  if (!(k(0, 0) > 0) || !(k(1, 1) > 0)) {
    *error = "fx and fy must be > 0";
    return false;
  }
  if (!(k(0, 2) >= -0.5 && k(0, 2) <= image_size.width - 0.5 && k(1, 2) >= -0.5 &&
        k(1, 2) <= image_size.height - 0.5)) {
    *error = "principal point (cx, cy) must lie inside the image";
    return false;
  }
  if (k(1, 0) != 0 || k(2, 0) != 0 || k(2, 1) != 0 || k(2, 2) != 1) {
    *error = "camera_matrix must be upper triangular with K(2,2) = 1";
    return false;
  }
  const size_t n = distortion.size();
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14) {
    *error =
        "distortion_coefficients must have 0, 4, 5, 8, 12 or 14 values, got " + std::to_string(n);
    return false;
  }
  for (double d : distortion) {
    if (!std::isfinite(d)) {
      *error = "distortion coefficients must be finite";
      return false;
    }
  }
  return true;
}

CameraIntrinsics CameraIntrinsics::ScaledTo(cv::Size size) const {
  CameraIntrinsics out = *this;
  const double sx = static_cast<double>(size.width) / image_size.width;
  const double sy = static_cast<double>(size.height) / image_size.height;
  out.image_size = size;
  // Pixel centres: x_new + 0.5 = (x_old + 0.5) * s.
  out.camera_matrix(0, 0) *= sx;
  out.camera_matrix(0, 1) *= sx;
  out.camera_matrix(0, 2) = (camera_matrix(0, 2) + 0.5) * sx - 0.5;
  out.camera_matrix(1, 1) *= sy;
  out.camera_matrix(1, 2) = (camera_matrix(1, 2) + 0.5) * sy - 0.5;
  return out;
}

bool LoadCameraIntrinsics(const std::string& path, CameraIntrinsics* intrinsics,
                          std::string* error) {
  CameraIntrinsics loaded;
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) {
      *error = path + ": cannot open calibration file";
      return false;
    }
    const cv::FileNode width = fs["image_width"];
    const cv::FileNode height = fs["image_height"];
    if (!width.isInt() || !height.isInt()) {
      *error = path + ": missing or non-integer image_width / image_height";
      return false;
    }
    loaded.image_size = cv::Size(static_cast<int>(width), static_cast<int>(height));
    cv::Mat k;
    fs["camera_matrix"] >> k;
    if (k.rows != 3 || k.cols != 3) {
      *error = path + ": camera_matrix missing or not 3x3";
      return false;
    }
    k.convertTo(k, CV_64F);
    loaded.camera_matrix = cv::Matx33d(k.ptr<double>());
    cv::Mat d;
    fs["distortion_coefficients"] >> d;
    if (!d.empty()) {
      if (d.rows != 1 && d.cols != 1) {
        *error = path + ": distortion_coefficients must be a row or a column vector";
        return false;
      }
      d.convertTo(d, CV_64F);
      d = d.reshape(1, 1);
      loaded.distortion.assign(d.ptr<double>(), d.ptr<double>() + d.cols);
    }
  } catch (const cv::Exception& e) {
    *error = path + ": cannot parse calibration file: " + e.msg;
    return false;
  }
  std::string reason;
  if (!loaded.IsValid(&reason)) {
    *error = path + ": " + reason;
    return false;
  }
  *intrinsics = loaded;
  return true;
}

bool SaveCameraIntrinsics(const std::string& path, const CameraIntrinsics& intrinsics,
                          std::string* error) {
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    if (!fs.isOpened()) {
      *error = path + ": cannot write calibration file";
      return false;
    }
    fs << "image_width" << intrinsics.image_size.width;
    fs << "image_height" << intrinsics.image_size.height;
    fs << "camera_matrix" << cv::Mat(intrinsics.camera_matrix);
    cv::Mat distortion(1, static_cast<int>(intrinsics.distortion.size()), CV_64F);
    for (size_t i = 0; i < intrinsics.distortion.size(); ++i) {
      distortion.at<double>(0, static_cast<int>(i)) = intrinsics.distortion[i];
    }
    fs << "distortion_coefficients" << distortion;
  } catch (const cv::Exception& e) {
    *error = path + ": " + e.msg;
    return false;
  }
  return true;
}

}  // namespace mostar::camera
