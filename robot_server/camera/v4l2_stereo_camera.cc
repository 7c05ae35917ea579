#include "robot_server/camera/v4l2_stereo_camera.h"

#include <cmath>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <utility>

#include "common/log/log.h"

namespace mostar::camera {

V4l2StereoCamera::V4l2StereoCamera(const Options& options)
    : options_(options), pairer_(options.pairing) {}

V4l2StereoCamera::~V4l2StereoCamera() { Close(); }

bool V4l2StereoCamera::OpenDevice(const std::string& device, cv::VideoCapture* capture,
                                  std::string* error) {
  try {
    char* end = nullptr;
    const long index = std::strtol(device.c_str(), &end, 10);
    const bool numeric = !device.empty() && end != nullptr && *end == '\0';
    const bool opened = numeric ? capture->open(static_cast<int>(index), cv::CAP_V4L2)
                                : capture->open(device, cv::CAP_V4L2);
    if (!opened) {
      *error = "v4l2: cannot open '" + device + "' (missing, busy or not a capture device)";
      return false;
    }
    if (options_.fourcc.size() == 4) {
      capture->set(cv::CAP_PROP_FOURCC,
                   cv::VideoWriter::fourcc(options_.fourcc[0], options_.fourcc[1],
                                           options_.fourcc[2], options_.fourcc[3]));
    }
    capture->set(cv::CAP_PROP_FRAME_WIDTH, options_.width_px);
    capture->set(cv::CAP_PROP_FRAME_HEIGHT, options_.height_px);
    capture->set(cv::CAP_PROP_FPS, options_.frame_rate_hz);
    capture->set(cv::CAP_PROP_BUFFERSIZE, 2);  // newest frames, little queueing in the driver
    if (options_.exposure >= 0) {
      capture->set(cv::CAP_PROP_AUTO_EXPOSURE, 1);  // V4L2 "manual" mode
      capture->set(cv::CAP_PROP_EXPOSURE, options_.exposure);
    }
    if (options_.gain >= 0) capture->set(cv::CAP_PROP_GAIN, options_.gain);
    const int width = static_cast<int>(capture->get(cv::CAP_PROP_FRAME_WIDTH));
    const int height = static_cast<int>(capture->get(cv::CAP_PROP_FRAME_HEIGHT));
    if (width != options_.width_px || height != options_.height_px) {
      *error = "v4l2: '" + device + "' does not support " + std::to_string(options_.width_px) +
               "x" + std::to_string(options_.height_px) + " (it offers " + std::to_string(width) +
               "x" + std::to_string(height) + ")";
      capture->release();
      return false;
    }
  } catch (const cv::Exception& e) {
    *error = "v4l2: '" + device + "': " + e.msg;
    capture->release();
    return false;
  }
  return true;
}

bool V4l2StereoCamera::Open(std::string* error) {
  Close();
  std::string pairing_error;
  if (!options_.pairing.IsValid(&pairing_error)) {
    *error = "v4l2: pairing options: " + pairing_error;
    return false;
  }
  if (!OpenDevice(options_.left_device, &left_, error)) return false;
  if (!OpenDevice(options_.right_device, &right_, error)) {
    left_.release();
    return false;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pairer_.Reset();
    open_ = true;
    stop_ = false;
    lost_message_.clear();
    width_px_ = options_.width_px;
    height_px_ = options_.height_px;
    frame_rate_hz_ = left_.get(cv::CAP_PROP_FPS);
  }
  left_thread_ = std::thread([this] { ReadLoop(true); });
  right_thread_ = std::thread([this] { ReadLoop(false); });
  return true;
}

void V4l2StereoCamera::ReadLoop(bool left) {
  cv::VideoCapture& capture = left ? left_ : right_;
  const std::string& device = left ? options_.left_device : options_.right_device;
  int failures = 0;
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
    }
    TimedImage frame;
    bool ok = false;
    try {
      ok = capture.grab();
      frame.stamp = options_.clock->Now();
      ok = ok && capture.retrieve(frame.image);
    } catch (const cv::Exception&) {
      ok = false;
    }
    if (ok && !frame.image.empty() && frame.image.channels() == 1) {
      cv::cvtColor(frame.image, frame.image, cv::COLOR_GRAY2BGR);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (!ok || frame.image.empty()) {
      if (++failures >= options_.max_read_failures) {
        lost_message_ = "v4l2: '" + device + "' stopped delivering frames (" +
                        std::to_string(failures) + " failed reads)";
        cv_.notify_all();
        return;
      }
      continue;
    }
    failures = 0;
    if (left) {
      pairer_.AddLeft(std::move(frame));
    } else {
      pairer_.AddRight(std::move(frame));
    }
    cv_.notify_all();
  }
}

GrabResult V4l2StereoCamera::Grab(Duration timeout, StereoImagePair* pair) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!open_) return GrabResult::Error(GrabStatus::kNotOpen, "v4l2 camera not open");
  std::optional<StereoImagePair> ready;
  const bool woke = cv_.wait_for(lock, timeout, [&] {
    if (!lost_message_.empty()) return true;
    ready = pairer_.PopPair();
    return ready.has_value();
  });
  if (!lost_message_.empty()) return GrabResult::Error(GrabStatus::kDeviceLost, lost_message_);
  if (!woke || !ready) {
    return GrabResult::Error(GrabStatus::kTimeout,
                             "v4l2: no matched pair (pending left " +
                                 std::to_string(pairer_.pending_left()) + ", right " +
                                 std::to_string(pairer_.pending_right()) + ")");
  }
  *pair = std::move(*ready);
  pair->sequence = sequence_++;
  const StereoPairerStats& stats = pairer_.stats();
  if (std::abs(stats.drift_ns_per_s) > 1e6) {
    MOSTAR_LOG_EVERY_SEC(WARNING, 30)
        << "v4l2 stereo: cameras drift by " << stats.drift_ns_per_s * 1e-6 << " ms/s";
  }
  return GrabResult::Ok();
}

void V4l2StereoCamera::Close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    open_ = false;
  }
  cv_.notify_all();
  if (left_thread_.joinable()) left_thread_.join();
  if (right_thread_.joinable()) right_thread_.join();
  left_.release();
  right_.release();
}

bool V4l2StereoCamera::IsOpen() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

StereoCameraInfo V4l2StereoCamera::Info() const {
  std::lock_guard<std::mutex> lock(mutex_);
  StereoCameraInfo info;
  info.backend = "v4l2";
  info.left_device = options_.left_device;
  info.right_device = options_.right_device;
  info.width_px = open_ ? width_px_ : options_.width_px;
  info.height_px = open_ ? height_px_ : options_.height_px;
  info.frame_rate_hz = open_ && frame_rate_hz_ > 0 ? frame_rate_hz_ : options_.frame_rate_hz;
  return info;
}

std::vector<std::pair<std::string, uint64_t>> V4l2StereoCamera::Counters() const {
  const StereoPairerStats stats = pairer_stats();
  const auto abs_us = [](double ns) {
    return static_cast<uint64_t>(std::llround(std::abs(ns) * 1e-3));
  };
  return {{"pair_dropped_left", stats.dropped_left + stats.dropped_pairs},
          {"pair_dropped_right", stats.dropped_right + stats.dropped_pairs},
          {"pair_skew_us_abs", abs_us(static_cast<double>(stats.mean_skew.count()))},
          {"pair_drift_us_per_s_abs", abs_us(stats.drift_ns_per_s)}};
}

StereoPairerStats V4l2StereoCamera::pairer_stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pairer_.stats();
}

}  // namespace mostar::camera
