#include "robot_server/camera/dc1394_stereo_camera.h"

#include <poll.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <utility>

namespace mostar::camera {
namespace {

struct ModeEntry {
  const char* name;
  dc1394video_mode_t mode;
  int width;
  int height;
  int coding;  // 0 YUV422 (UYVY), 1 RGB8, 2 MONO8
};

constexpr ModeEntry kModes[] = {
    {"320x240_YUV422", DC1394_VIDEO_MODE_320x240_YUV422, 320, 240, 0},
    {"640x480_YUV422", DC1394_VIDEO_MODE_640x480_YUV422, 640, 480, 0},
    {"640x480_RGB8", DC1394_VIDEO_MODE_640x480_RGB8, 640, 480, 1},
    {"640x480_MONO8", DC1394_VIDEO_MODE_640x480_MONO8, 640, 480, 2},
    {"800x600_YUV422", DC1394_VIDEO_MODE_800x600_YUV422, 800, 600, 0},
    {"800x600_RGB8", DC1394_VIDEO_MODE_800x600_RGB8, 800, 600, 1},
    {"800x600_MONO8", DC1394_VIDEO_MODE_800x600_MONO8, 800, 600, 2},
    {"1024x768_YUV422", DC1394_VIDEO_MODE_1024x768_YUV422, 1024, 768, 0},
    {"1024x768_RGB8", DC1394_VIDEO_MODE_1024x768_RGB8, 1024, 768, 1},
    {"1024x768_MONO8", DC1394_VIDEO_MODE_1024x768_MONO8, 1024, 768, 2},
    {"1280x960_YUV422", DC1394_VIDEO_MODE_1280x960_YUV422, 1280, 960, 0},
    {"1280x960_RGB8", DC1394_VIDEO_MODE_1280x960_RGB8, 1280, 960, 1},
    {"1280x960_MONO8", DC1394_VIDEO_MODE_1280x960_MONO8, 1280, 960, 2},
};

struct RateEntry {
  double hz;
  dc1394framerate_t rate;
};
constexpr RateEntry kRates[] = {
    {1.875, DC1394_FRAMERATE_1_875}, {3.75, DC1394_FRAMERATE_3_75}, {7.5, DC1394_FRAMERATE_7_5},
    {15, DC1394_FRAMERATE_15},       {30, DC1394_FRAMERATE_30},     {60, DC1394_FRAMERATE_60},
    {120, DC1394_FRAMERATE_120},     {240, DC1394_FRAMERATE_240},
};

std::string GuidString(uint64_t guid) {
  char text[32];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(guid));
  return text;
}

bool Check(dc1394error_t err, const std::string& what, std::string* error) {
  if (err == DC1394_SUCCESS) return true;
  *error = "dc1394: " + what + ": " + dc1394_error_get_string(err);
  return false;
}

// Dequeues one frame, waiting at most until `deadline` (monotonic). Null on timeout.
dc1394video_frame_t* Dequeue(dc1394camera_t* camera, std::chrono::steady_clock::time_point deadline,
                             bool* failed) {
  *failed = false;
  for (;;) {
    dc1394video_frame_t* frame = nullptr;
    if (dc1394_capture_dequeue(camera, DC1394_CAPTURE_POLICY_POLL, &frame) != DC1394_SUCCESS) {
      *failed = true;
      return nullptr;
    }
    if (frame != nullptr) return frame;
    const auto left = deadline - std::chrono::steady_clock::now();
    if (left <= std::chrono::steady_clock::duration::zero()) return nullptr;
    pollfd fd{dc1394_capture_get_fileno(camera), POLLIN, 0};
    const int ms =
        static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(left).count() + 1);
    if (poll(&fd, 1, ms) < 0) {
      *failed = true;
      return nullptr;
    }
  }
}

}  // namespace

Dc1394StereoCamera::Dc1394StereoCamera(const Options& options) : options_(options) {}

Dc1394StereoCamera::~Dc1394StereoCamera() { Close(); }

bool Dc1394StereoCamera::Configure(dc1394camera_t* camera, const char* eye, bool* capturing,
                                   std::string* error) {
  const std::string who = std::string(eye) + " camera " + GuidString(camera->guid);
  const ModeEntry* mode = nullptr;
  for (const ModeEntry& entry : kModes) {
    if (options_.video_mode == entry.name) mode = &entry;
  }
  if (mode == nullptr) {
    *error = "dc1394: unsupported video_mode '" + options_.video_mode +
             "' (use e.g. 640x480_YUV422, 640x480_RGB8, 640x480_MONO8)";
    return false;
  }
  const RateEntry* rate = nullptr;
  for (const RateEntry& entry : kRates) {
    if (std::abs(entry.hz - options_.frame_rate_hz) < 1e-3) rate = &entry;
  }
  if (rate == nullptr) {
    *error = "dc1394: frame_rate_hz " + std::to_string(options_.frame_rate_hz) +
             " is not an IIDC rate (1.875, 3.75, 7.5, 15, 30, 60, 120, 240)";
    return false;
  }
  dc1394speed_t speed;
  switch (options_.iso_speed_mbps) {
    case 100:
      speed = DC1394_ISO_SPEED_100;
      break;
    case 200:
      speed = DC1394_ISO_SPEED_200;
      break;
    case 400:
      speed = DC1394_ISO_SPEED_400;
      break;
    case 800:
      speed = DC1394_ISO_SPEED_800;
      break;
    default:
      *error = "dc1394: iso_speed_mbps must be 100, 200, 400 or 800";
      return false;
  }
  if (options_.dma_buffers < 2) {
    *error = "dc1394: dma_buffers must be >= 2";
    return false;
  }
  const dc1394operation_mode_t operation =
      speed >= DC1394_ISO_SPEED_800 ? DC1394_OPERATION_MODE_1394B : DC1394_OPERATION_MODE_LEGACY;
  if (!Check(dc1394_video_set_operation_mode(camera, operation), who + ": operation mode", error) ||
      !Check(dc1394_video_set_iso_speed(camera, speed), who + ": ISO speed", error) ||
      !Check(dc1394_video_set_mode(camera, mode->mode), who + ": video mode " + mode->name,
             error) ||
      !Check(dc1394_video_set_framerate(camera, rate->rate), who + ": frame rate", error)) {
    return false;
  }
  const auto set_feature = [&](dc1394feature_t feature, int value, const char* name) {
    if (value < 0) {
      return Check(dc1394_feature_set_mode(camera, feature, DC1394_FEATURE_MODE_AUTO),
                   who + ": auto " + name, error);
    }
    return Check(dc1394_feature_set_mode(camera, feature, DC1394_FEATURE_MODE_MANUAL),
                 who + ": manual " + name, error) &&
           Check(dc1394_feature_set_value(camera, feature, static_cast<uint32_t>(value)),
                 who + ": " + name + " value", error);
  };
  // Cameras without a feature refuse it; only manual values are required to work.
  if (options_.exposure >= 0) {
    if (!set_feature(DC1394_FEATURE_EXPOSURE, options_.exposure, "exposure")) return false;
  } else {
    set_feature(DC1394_FEATURE_EXPOSURE, -1, "exposure");
  }
  if (!set_feature(DC1394_FEATURE_SHUTTER, options_.shutter, "shutter") && options_.shutter >= 0) {
    return false;
  }
  if (!set_feature(DC1394_FEATURE_GAIN, options_.gain, "gain") && options_.gain >= 0) {
    return false;
  }
  error->clear();
  if (!Check(dc1394_capture_setup(camera, static_cast<uint32_t>(options_.dma_buffers),
                                  DC1394_CAPTURE_FLAGS_DEFAULT),
             who + ": DMA capture setup (bandwidth or buffers exhausted?)", error)) {
    return false;
  }
  *capturing = true;
  if (!Check(dc1394_video_set_transmission(camera, DC1394_ON), who + ": start transmission",
             error)) {
    return false;
  }
  width_px_ = mode->width;
  height_px_ = mode->height;
  coding_ = mode->coding;
  return true;
}

bool Dc1394StereoCamera::Open(std::string* error) {
  Close();
  context_ = dc1394_new();
  if (context_ == nullptr) {
    *error =
        "no IEEE1394 camera found: libdc1394 cannot access a FireWire bus (no /dev/fw* device: "
        "is the firewire-ohci module loaded and are the udev rules installed?)";
    return false;
  }
  dc1394camera_list_t* list = nullptr;
  const dc1394error_t err = dc1394_camera_enumerate(context_, &list);
  if (err != DC1394_SUCCESS || list == nullptr) {
    *error = std::string("no IEEE1394 camera found: enumeration failed: ") +
             dc1394_error_get_string(err);
    Close();
    return false;
  }
  const uint32_t count = list->num;
  uint64_t left_guid = options_.left_guid;
  uint64_t right_guid = options_.right_guid;
  std::string found;
  for (uint32_t i = 0; i < count; ++i) found += (i ? ", " : "") + GuidString(list->ids[i].guid);
  if (left_guid == 0 && count > 0) left_guid = list->ids[0].guid;
  if (right_guid == 0) {
    for (uint32_t i = 0; i < count; ++i) {
      if (list->ids[i].guid != left_guid) {
        right_guid = list->ids[i].guid;
        break;
      }
    }
  }
  dc1394_camera_free_list(list);
  if (count == 0) {
    *error = "no IEEE1394 camera found on the FireWire bus (stereo needs two)";
    Close();
    return false;
  }
  if (right_guid == 0 || left_guid == right_guid) {
    *error = "only one IEEE1394 camera found (" + found + "); stereo needs two";
    Close();
    return false;
  }
  left_ = dc1394_camera_new(context_, left_guid);
  right_ = dc1394_camera_new(context_, right_guid);
  if (left_ == nullptr || right_ == nullptr) {
    *error = "no IEEE1394 camera found with GUID " +
             GuidString(left_ == nullptr ? left_guid : right_guid) + " (on the bus: " + found + ")";
    Close();
    return false;
  }
  if (!Configure(left_, "left", &left_capturing_, error) ||
      !Configure(right_, "right", &right_capturing_, error)) {
    Close();
    return false;
  }
  left_guid_ = left_guid;
  right_guid_ = right_guid;
  open_ = true;
  return true;
}

GrabResult Dc1394StereoCamera::Grab(Duration timeout, StereoImagePair* pair) {
  if (!open_) return GrabResult::Error(GrabStatus::kNotOpen, "dc1394 camera not open");
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(timeout);
  bool failed = false;
  // Newest frame of a camera: dequeue, then skip frames the ring still holds behind it.
  const auto newest = [&](dc1394camera_t* camera) -> dc1394video_frame_t* {
    dc1394video_frame_t* frame = Dequeue(camera, deadline, &failed);
    while (frame != nullptr && frame->frames_behind > 0) {
      dc1394_capture_enqueue(camera, frame);
      ++dropped_frames_;
      frame = Dequeue(camera, deadline, &failed);
    }
    return frame;
  };
  dc1394video_frame_t* left = newest(left_);
  dc1394video_frame_t* right = left != nullptr ? newest(right_) : nullptr;
  const int64_t max_skew_us =
      std::chrono::duration_cast<std::chrono::microseconds>(options_.max_skew).count();
  while (left != nullptr && right != nullptr) {
    const int64_t skew_us =
        static_cast<int64_t>(left->timestamp) - static_cast<int64_t>(right->timestamp);
    if (std::llabs(skew_us) <= max_skew_us) break;
    ++dropped_frames_;
    if (skew_us < 0) {
      dc1394_capture_enqueue(left_, left);
      left = Dequeue(left_, deadline, &failed);
    } else {
      dc1394_capture_enqueue(right_, right);
      right = Dequeue(right_, deadline, &failed);
    }
  }
  if (left == nullptr || right == nullptr) {
    if (left != nullptr) dc1394_capture_enqueue(left_, left);
    if (right != nullptr) dc1394_capture_enqueue(right_, right);
    if (failed) {
      return GrabResult::Error(GrabStatus::kDeviceLost,
                               "dc1394: capture failed (camera unplugged or bus reset)");
    }
    return GrabResult::Error(GrabStatus::kTimeout, "dc1394: no matched pair within timeout");
  }
  const auto convert = [&](dc1394video_frame_t* frame, cv::Mat* out) {
    const int width = static_cast<int>(frame->size[0]);
    const int height = static_cast<int>(frame->size[1]);
    switch (coding_) {
      case 0:
        cv::cvtColor(cv::Mat(height, width, CV_8UC2, frame->image), *out, cv::COLOR_YUV2BGR_UYVY);
        break;
      case 1:
        cv::cvtColor(cv::Mat(height, width, CV_8UC3, frame->image), *out, cv::COLOR_RGB2BGR);
        break;
      default: {
        const cv::Mat raw(height, width, CV_8UC1, frame->image);
        const std::string& bayer = options_.bayer_pattern;
        const int code = bayer == "RGGB"   ? cv::COLOR_BayerBG2BGR
                         : bayer == "GRBG" ? cv::COLOR_BayerGB2BGR
                         : bayer == "GBRG" ? cv::COLOR_BayerGR2BGR
                         : bayer == "BGGR" ? cv::COLOR_BayerRG2BGR
                                           : cv::COLOR_GRAY2BGR;
        cv::cvtColor(raw, *out, code);
      }
    }
  };
  convert(left, &pair->left);
  convert(right, &pair->right);
  const int64_t stamp_us =
      (static_cast<int64_t>(left->timestamp) + static_cast<int64_t>(right->timestamp)) / 2;
  pair->stamp = FromUnixNanos(stamp_us * 1000);
  pair->sequence = sequence_++;
  dc1394_capture_enqueue(left_, left);
  dc1394_capture_enqueue(right_, right);
  return GrabResult::Ok();
}

void Dc1394StereoCamera::Close() {
  const std::pair<dc1394camera_t**, bool*> cameras[] = {{&left_, &left_capturing_},
                                                        {&right_, &right_capturing_}};
  for (const auto& [camera, capturing] : cameras) {
    if (*camera == nullptr) continue;
    if (*capturing) {
      dc1394_video_set_transmission(*camera, DC1394_OFF);
      dc1394_capture_stop(*camera);
      *capturing = false;
    }
    dc1394_camera_free(*camera);
    *camera = nullptr;
  }
  if (context_ != nullptr) {
    dc1394_free(context_);
    context_ = nullptr;
  }
  open_ = false;
}

StereoCameraInfo Dc1394StereoCamera::Info() const {
  StereoCameraInfo info;
  info.backend = "dc1394";
  info.left_device = "guid:" + GuidString(open_ ? left_guid_ : options_.left_guid);
  info.right_device = "guid:" + GuidString(open_ ? right_guid_ : options_.right_guid);
  info.width_px = width_px_;
  info.height_px = height_px_;
  info.frame_rate_hz = options_.frame_rate_hz;
  return info;
}

}  // namespace mostar::camera
