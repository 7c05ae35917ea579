// JPEG encoding with libjpeg-turbo (its libjpeg API, BGR in, no colour conversion pass), and
// the stereo compressor that encodes both eyes in parallel. Decoding: common/jpeg/jpeg_decoder.h.
//
// libjpeg-turbo directly was measured faster than OpenCV's imencode on the same library (see
// camera_benchmark), and it lets a damaged JPEG be reported as an error instead of a warning
// on stderr and a grey-filled image.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <opencv2/core/mat.hpp>
#include <string>
#include <thread>
#include <vector>

#include "common/types/stereo_frame.h"
#include "robot_server/camera/stereo_camera.h"

namespace mostar::camera {

struct JpegSettings {
  int quality = 80;    // libjpeg quality, 1..100
  double scale = 1.0;  // image downscale before encoding, (0, 1]; 1 = full resolution
  bool IsValid(std::string* error) const;
};

// Encodes one image at a time; keeps its libjpeg state between calls. Not thread-safe.
class JpegEncoder {
 public:
  JpegEncoder();
  ~JpegEncoder();
  JpegEncoder(const JpegEncoder&) = delete;
  JpegEncoder& operator=(const JpegEncoder&) = delete;

  // Encodes `bgr` (CV_8UC3, or CV_8UC1 as grey) into `out` (replaced; its capacity is reused).
  // False with a message on empty/unsupported input or a libjpeg error.
  bool Encode(const cv::Mat& bgr, const JpegSettings& settings, std::vector<uint8_t>* out,
              std::string* error);

  struct State;  // libjpeg state (implementation detail)

 private:
  std::unique_ptr<State> state_;
  cv::Mat scaled_;
};

// Compresses both eyes of a pair into a CompressedStereoPair (frame ids "camera_left" /
// "camera_right", format "jpeg", the pair's stamp on both). With `parallel`, the left eye is
// encoded on an internal worker thread while the calling thread encodes the right eye.
// Compress() is called from one thread at a time (the pipeline's compression thread).
class JpegCompressor {
 public:
  explicit JpegCompressor(bool parallel = true);
  ~JpegCompressor();
  JpegCompressor(const JpegCompressor&) = delete;
  JpegCompressor& operator=(const JpegCompressor&) = delete;

  bool Compress(const StereoImagePair& pair, const JpegSettings& settings,
                CompressedStereoPair* out, std::string* error);

 private:
  void WorkerLoop();

  const bool parallel_;
  JpegEncoder left_encoder_;
  JpegEncoder right_encoder_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  bool job_pending_ = false;
  bool job_done_ = false;
  const cv::Mat* job_image_ = nullptr;
  JpegSettings job_settings_;
  std::vector<uint8_t>* job_out_ = nullptr;
  bool job_ok_ = false;
  std::string job_error_;
  std::thread worker_;
};

}  // namespace mostar::camera
