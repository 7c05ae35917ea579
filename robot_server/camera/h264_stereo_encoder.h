// Encodes both eyes of each stereo pair into two H.264 streams that advance together: one
// StereoVideoFrame per pair, AU n of the left stream and AU n of the right one from the same
// capture, both IDRs or neither (common/h264/h264_encoder.h does each eye).
//
// The encoders are made on the first pair and made again when the pair's size changes (the
// first AU of new encoders is an IDR). The target bitrate is for both eyes together, split
// evenly. An IDR is forced on both eyes together (ForceIdr, or after an encoding error), so a
// viewer that waits for an IDR resumes both eyes on the same pair. AU numbers go up by one per
// pair encoded, and also per pair that failed: a viewer then sees a gap, and the next AU is an
// IDR anyway. With `parallel`, the left eye is encoded on an internal worker thread while the
// calling thread encodes the right one. Encode() is called from one thread at a time.
#pragma once

#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "common/h264/h264_encoder.h"
#include "common/types/stereo_frame.h"
#include "robot_server/camera/stereo_camera.h"

namespace mostar::camera {

struct H264StreamOptions {
  std::string preset = "ultrafast";  // x264 preset
  int keyint_frames = 300;           // IDR (or intra refresh) period, frames
  bool intra_refresh = false;        // periodic intra refresh instead of periodic IDRs
  double vbv_frames = 1.0;           // VBV buffer in frames: small = even frame sizes
  int threads_per_eye = 1;           // x264 slice threads per eye; 0 = x264's choice
  // Both eyes' bitrate when the pipeline's target is unlimited (the "lan" class), bit/s.
  double unlimited_bits_per_s = 16e6;
  bool IsValid(std::string* error) const;
};

class H264StereoEncoder {
 public:
  H264StereoEncoder(const H264StreamOptions& options, int frame_rate_hz, bool parallel);
  ~H264StereoEncoder();
  H264StereoEncoder(const H264StereoEncoder&) = delete;
  H264StereoEncoder& operator=(const H264StereoEncoder&) = delete;

  // Encodes `pair` (both eyes the same even size) at `bits_per_s` for both eyes (<= 0: the
  // unlimited rate) into `out` (format "h264"). False with `error` when the encoders cannot be
  // made or an eye fails; the AU number is used up and the next pair is an IDR.
  bool Encode(const StereoImagePair& pair, double bits_per_s, StereoVideoFrame* out,
              std::string* error);
  // The next pair encoded is an IDR on both eyes.
  void ForceIdr() { force_idr_ = true; }
  // Both eyes' bitrate the encoders were last set to, bit/s (0 before the first pair).
  int bitrate_bps() const { return 2 * eye_bitrate_bps_; }
  uint64_t restarts() const { return restarts_; }  // encoders made (size changes included)

 private:
  bool EnsureEncoders(int width_px, int height_px, int eye_bits_per_s, std::string* error);
  void WorkerLoop();

  const H264StreamOptions options_;
  const int frame_rate_hz_;
  const bool parallel_;
  std::unique_ptr<h264::Encoder> left_;
  std::unique_ptr<h264::Encoder> right_;
  bool force_idr_ = false;
  int eye_bitrate_bps_ = 0;
  uint64_t next_sequence_ = 1;  // 0 stays "no AU yet" for viewers
  uint64_t restarts_ = 0;

  std::mutex mutex_;  // guards the job below
  std::condition_variable cv_;
  bool stop_ = false;
  std::function<void()> job_;
  bool job_done_ = false;
  std::thread worker_;
};

}  // namespace mostar::camera
