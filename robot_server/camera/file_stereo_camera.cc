#include "robot_server/camera/file_stereo_camera.h"

#include <algorithm>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

namespace mostar::camera {
namespace {

bool ToBgr(cv::Mat* image) {
  if (image->empty()) return false;
  if (image->depth() != CV_8U) image->convertTo(*image, CV_8U);
  if (image->channels() == 1) {
    cv::cvtColor(*image, *image, cv::COLOR_GRAY2BGR);
  } else if (image->channels() == 4) {
    cv::cvtColor(*image, *image, cv::COLOR_BGRA2BGR);
  }
  return image->channels() == 3;
}

SteadyTime RealSteadyNow() {
  return SteadyTime(std::chrono::steady_clock::now().time_since_epoch());
}

}  // namespace

FileStereoCamera::FileStereoCamera(const Options& options) : options_(options) {}

FileStereoCamera::~FileStereoCamera() { Close(); }

bool FileStereoCamera::Open(std::string* error) {
  Close();
  width_px_ = 0;
  height_px_ = 0;
  if (!(options_.frame_rate_hz > 0)) {
    *error = "file camera: frame_rate_hz must be > 0";
    return false;
  }
  try {
    switch (options_.source) {
      case Source::kTwoImageSequences: {
        cv::glob(options_.left, left_files_, false);
        cv::glob(options_.right, right_files_, false);
        if (left_files_.empty()) {
          *error = "file camera: no image matches '" + options_.left + "'";
          return false;
        }
        if (left_files_.size() != right_files_.size()) {
          *error = "file camera: " + std::to_string(left_files_.size()) + " left images ('" +
                   options_.left + "') but " + std::to_string(right_files_.size()) +
                   " right images ('" + options_.right + "')";
          return false;
        }
        break;
      }
      case Source::kTwoVideos:
        if (!left_video_.open(options_.left) || !right_video_.open(options_.right)) {
          *error = "file camera: cannot open video '" +
                   (left_video_.isOpened() ? options_.right : options_.left) + "'";
          Close();
          return false;
        }
        break;
      case Source::kSideBySideVideo:
        if (!left_video_.open(options_.left)) {
          *error = "file camera: cannot open side-by-side video '" + options_.left + "'";
          return false;
        }
        break;
    }
  } catch (const cv::Exception& e) {
    *error = "file camera: " + e.msg;
    Close();
    return false;
  }
  // Read the first pair to learn (and check) the size, then start again.
  cv::Mat left, right;
  bool end = false;
  if (!ReadNext(&left, &right, error, &end)) {
    if (end) *error = "file camera: no frames in '" + options_.left + "'";
    Close();
    return false;
  }
  width_px_ = left.cols;
  height_px_ = left.rows;
  if (!Rewind(error)) {
    Close();
    return false;
  }
  open_ = true;
  next_due_ = RealSteadyNow();
  return true;
}

bool FileStereoCamera::Rewind(std::string* error) {
  next_index_ = 0;
  if (options_.source == Source::kTwoImageSequences) return true;
  // Reopening is more reliable than seeking for every container.
  left_video_.release();
  right_video_.release();
  if (!left_video_.open(options_.left) ||
      (options_.source == Source::kTwoVideos && !right_video_.open(options_.right))) {
    *error = "file camera: cannot reopen video for looping";
    return false;
  }
  return true;
}

bool FileStereoCamera::ReadNext(cv::Mat* left, cv::Mat* right, std::string* error, bool* end) {
  *end = false;
  switch (options_.source) {
    case Source::kTwoImageSequences: {
      if (next_index_ >= left_files_.size()) {
        *end = true;
        *error = "file camera: end of image sequence";
        return false;
      }
      const std::string& left_path = left_files_[next_index_];
      const std::string& right_path = right_files_[next_index_];
      ++next_index_;
      *left = cv::imread(left_path, cv::IMREAD_UNCHANGED);
      *right = cv::imread(right_path, cv::IMREAD_UNCHANGED);
      if (!ToBgr(left) || !ToBgr(right)) {
        *error =
            "file camera: cannot read image '" + (left->empty() ? left_path : right_path) + "'";
        return false;
      }
      break;
    }
    case Source::kTwoVideos: {
      if (!left_video_.read(*left) || !right_video_.read(*right)) {
        *end = true;
        *error = "file camera: end of video";
        return false;
      }
      if (!ToBgr(left) || !ToBgr(right)) {
        *error = "file camera: unsupported video pixel format";
        return false;
      }
      break;
    }
    case Source::kSideBySideVideo: {
      cv::Mat both;
      if (!left_video_.read(both)) {
        *end = true;
        *error = "file camera: end of video";
        return false;
      }
      if (!ToBgr(&both) || both.cols < 2) {
        *error = "file camera: unsupported video pixel format";
        return false;
      }
      const int half = both.cols / 2;
      *left = both(cv::Rect(0, 0, half, both.rows)).clone();
      *right = both(cv::Rect(half, 0, half, both.rows)).clone();
      break;
    }
  }
  if (left->size() != right->size()) {
    *error = "file camera: left and right images differ in size";
    return false;
  }
  if (width_px_ > 0 && (left->cols != width_px_ || left->rows != height_px_)) {
    *error = "file camera: image size changed within the stream";
    return false;
  }
  return true;
}

GrabResult FileStereoCamera::Grab(Duration timeout, StereoImagePair* pair) {
  if (!open_) return GrabResult::Error(GrabStatus::kNotOpen, "file camera not open");
  if (options_.paced) {
    const SteadyTime now = RealSteadyNow();
    if (next_due_ - now > timeout) {
      std::this_thread::sleep_for(timeout);
      return GrabResult::Error(GrabStatus::kTimeout, "file camera: next frame not due yet");
    }
    if (next_due_ > now) std::this_thread::sleep_for(next_due_ - now);
    next_due_ = std::max(next_due_, now - FromSeconds(1.0 / options_.frame_rate_hz)) +
                FromSeconds(1.0 / options_.frame_rate_hz);
  }
  std::string error;
  bool end = false;
  if (!ReadNext(&pair->left, &pair->right, &error, &end)) {
    if (end && options_.loop) {
      if (!Rewind(&error) || !ReadNext(&pair->left, &pair->right, &error, &end)) {
        return GrabResult::Error(GrabStatus::kDeviceLost, error);
      }
    } else {
      return GrabResult::Error(end ? GrabStatus::kEndOfStream : GrabStatus::kDeviceLost, error);
    }
  }
  pair->sequence = sequence_++;
  pair->stamp = options_.clock->Now();
  return GrabResult::Ok();
}

void FileStereoCamera::Close() {
  open_ = false;
  left_video_.release();
  right_video_.release();
  left_files_.clear();
  right_files_.clear();
  next_index_ = 0;
}

StereoCameraInfo FileStereoCamera::Info() const {
  StereoCameraInfo info;
  info.backend = "file";
  info.left_device = options_.left;
  info.right_device = options_.source == Source::kSideBySideVideo ? options_.left : options_.right;
  info.width_px = width_px_;
  info.height_px = height_px_;
  info.frame_rate_hz = options_.paced ? options_.frame_rate_hz : 0;
  return info;
}

}  // namespace mostar::camera
