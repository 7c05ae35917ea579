#include "robot_server/camera/camera_factory.h"

#include <algorithm>
#include <cmath>

#include "robot_server/camera/fake_stereo_camera.h"
#include "robot_server/camera/file_stereo_camera.h"
#include "robot_server/camera/v4l2_stereo_camera.h"
#ifdef MOSTAR_HAVE_DC1394
#include "robot_server/camera/dc1394_stereo_camera.h"
#endif

namespace mostar::camera {

CameraPipelineOptions MakePipelineOptions(const CameraConfig& config) {
  CameraPipelineOptions options;
  options.name = config.name();
  options.grab_timeout = FromMilliseconds(config.grab_timeout_ms());
  options.max_consecutive_timeouts = config.max_consecutive_timeouts();
  options.reopen_period = FromMilliseconds(config.reopen_period_ms());
  options.parallel_compression = config.parallel_compression();
  const BitrateConfig& bitrate = config.bitrate();
  if (bitrate.classes_size() > 0) {
    options.bitrate_classes.clear();
    for (const BitrateClassConfig& c : bitrate.classes()) {
      options.bitrate_classes[c.name()] = c.target_bits_per_s();
    }
  }
  BitrateControllerOptions& controller = options.bitrate;
  controller.min_quality = bitrate.min_quality();
  controller.max_quality = bitrate.max_quality();
  controller.initial_quality =
      std::clamp(config.jpeg_quality(), bitrate.min_quality(), bitrate.max_quality());
  if (bitrate.scales_size() > 0) {
    controller.scales.assign(bitrate.scales().begin(), bitrate.scales().end());
  } else {
    controller.scales = DefaultScaleLadder(config.width_px());
  }
  controller.max_frame_rate_divisor = bitrate.max_frame_rate_divisor();
  controller.headroom = bitrate.headroom();
  controller.min_link_bits_per_s = bitrate.min_link_bits_per_s();
  const auto it = options.bitrate_classes.find(bitrate.initial_class());
  controller.target_bits_per_s = it != options.bitrate_classes.end() ? it->second : 0;
  options.codec = config.codec() == CameraConfig::H264 ? VideoCodec::kH264 : VideoCodec::kJpeg;
  options.frame_rate_hz = std::max(1, static_cast<int>(std::lround(config.fps())));
  const H264Config& h264 = config.h264();
  options.h264.preset = h264.preset();
  options.h264.keyint_frames = h264.keyint_frames();
  options.h264.intra_refresh = h264.intra_refresh();
  options.h264.vbv_frames = h264.vbv_frames();
  options.h264.threads_per_eye = h264.threads_per_eye();
  options.h264.unlimited_bits_per_s = h264.unlimited_bits_per_s();
  return options;
}

bool ValidateCameraConfig(const CameraConfig& config, std::string* error) {
  const BitrateConfig& bitrate = config.bitrate();
  if (bitrate.min_quality() > bitrate.max_quality()) {
    *error = "bitrate.min_quality: must be <= bitrate.max_quality";
    return false;
  }
  const CameraPipelineOptions options = MakePipelineOptions(config);
  if (options.bitrate_classes.count(bitrate.initial_class()) == 0) {
    *error = "bitrate.initial_class: '" + bitrate.initial_class() + "' is not a bitrate class";
    return false;
  }
  std::string reason;
  if (config.codec() == CameraConfig::H264 && !options.h264.IsValid(&reason)) {
    *error = "h264: " + reason;
    return false;
  }
  if (config.codec() == CameraConfig::H264 && (config.width_px() % 2 || config.height_px() % 2)) {
    *error = "width_px and height_px must be even for codec H264";
    return false;
  }
  if (!options.IsValid(&reason)) {
    *error = "bitrate: " + reason;
    return false;
  }
  if (config.backend() == CameraConfig::FILE && config.file().left().empty()) {
    *error = "file.left: required for the FILE backend";
    return false;
  }
  if (config.backend() == CameraConfig::FILE &&
      config.file().source() != FileCameraConfig::SIDE_BY_SIDE_VIDEO &&
      config.file().right().empty()) {
    *error = "file.right: required unless file.source is SIDE_BY_SIDE_VIDEO";
    return false;
  }
  if (config.backend() == CameraConfig::REPLAY && config.replay().file().empty()) {
    *error = "replay.file: required for the REPLAY backend";
    return false;
  }
  return true;
}

std::unique_ptr<StereoCamera> MakeStereoCamera(const CameraConfig& config, const Clock* clock,
                                               std::string* error) {
  if (!ValidateCameraConfig(config, error)) return nullptr;
  switch (config.backend()) {
    case CameraConfig::V4L2: {
      V4l2StereoCamera::Options options;
      options.left_device = config.v4l2().left_device();
      options.right_device = config.v4l2().right_device();
      options.width_px = config.width_px();
      options.height_px = config.height_px();
      options.frame_rate_hz = config.fps();
      options.fourcc = config.v4l2().fourcc();
      options.exposure = config.v4l2().exposure();
      options.gain = config.v4l2().gain();
      options.pairing.max_skew = FromMilliseconds(config.v4l2().max_skew_ms());
      options.clock = clock;
      return std::make_unique<V4l2StereoCamera>(options);
    }
    case CameraConfig::DC1394: {
#ifdef MOSTAR_HAVE_DC1394
      Dc1394StereoCamera::Options options;
      const Dc1394CameraConfig& dc = config.dc1394();
      options.left_guid = dc.left_guid();
      options.right_guid = dc.right_guid();
      options.video_mode = dc.video_mode();
      options.bayer_pattern = dc.bayer_pattern();
      options.frame_rate_hz = config.fps();
      options.iso_speed_mbps = dc.iso_speed_mbps();
      options.dma_buffers = dc.dma_buffers();
      options.exposure = dc.exposure();
      options.shutter = dc.shutter();
      options.gain = dc.gain();
      options.max_skew = FromMilliseconds(dc.max_skew_ms());
      return std::make_unique<Dc1394StereoCamera>(options);
#else
      *error = "backend: DC1394 is not available (built without libdc1394-2)";
      return nullptr;
#endif
    }
    case CameraConfig::FILE: {
      FileStereoCamera::Options options;
      switch (config.file().source()) {
        case FileCameraConfig::IMAGE_SEQUENCES:
          options.source = FileStereoCamera::Source::kTwoImageSequences;
          break;
        case FileCameraConfig::TWO_VIDEOS:
          options.source = FileStereoCamera::Source::kTwoVideos;
          break;
        case FileCameraConfig::SIDE_BY_SIDE_VIDEO:
          options.source = FileStereoCamera::Source::kSideBySideVideo;
          break;
      }
      options.left = config.file().left();
      options.right = config.file().right();
      options.frame_rate_hz = config.fps();
      options.paced = config.file().paced();
      options.loop = config.file().loop();
      options.clock = clock;
      return std::make_unique<FileStereoCamera>(options);
    }
    case CameraConfig::FAKE: {
      FakeStereoCamera::Options options;
      options.width_px = config.width_px();
      options.height_px = config.height_px();
      options.frame_rate_hz = config.fps();
      options.free_run = true;
      options.paced = true;
      options.clock = clock;
      return std::make_unique<FakeStereoCamera>(options);
    }
    case CameraConfig::SIM:
      *error = "backend: SIM cameras are created by the simulator wiring, not by this factory";
      return nullptr;
    case CameraConfig::REPLAY:
      *error =
          "backend: REPLAY cameras are created by the server wiring (robot_server/replay), "
          "not by this factory";
      return nullptr;
  }
  *error = "backend: unknown value";
  return nullptr;
}

}  // namespace mostar::camera
