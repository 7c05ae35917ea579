// H.264 encoding for the robot's video over the WAN: libx264 through libavcodec, tuned for the
// lowest delay (tune=zerolatency: no B-frames, no lookahead; one access unit out for every
// frame in, in the same call). Each access unit is Annex B with SPS and PPS in-band on every IDR,
// which is what foxglove_msgs/CompressedVideo asks for (common/h264/annexb.h).
//
// Rate: VBV through the codec context (bit_rate = rc_max_rate, a buffer of `vbv_frames` frames),
// the only way libavcodec 5.1 lets the target change while encoding (SetBitrate). Recovery: an
// IDR on request (ForceIdr: a reader lost data or joined) and, optionally, periodic intra
// refresh instead of periodic IDRs (no keyframe spikes on a thin uplink).
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace mostar::h264 {

struct EncoderSettings {
  int width_px = 640;  // even, >= 16
  int height_px = 480;
  int frame_rate_hz = 30;            // nominal, 1..120 (the rate control's time base)
  int bitrate_bps = 2'000'000;       // target and VBV maximum, >= 50 kbit/s
  double vbv_frames = 1.0;           // VBV buffer in frames at the target rate, (0, 30]
  int keyint_frames = 300;           // IDR period (or intra refresh period), >= 1
  bool intra_refresh = false;        // periodic intra refresh instead of periodic IDRs
  std::string preset = "ultrafast";  // x264 preset
  int threads = 1;                   // x264 slice threads; 0 = x264's choice
  bool IsValid(std::string* error) const;
};

struct EncodedFrame {
  std::vector<uint8_t> data;  // one access unit, Annex B
  bool idr = false;           // holds an IDR slice with its SPS and PPS: decoding may start here
  int64_t frame_index = 0;    // 0, 1, ... in input order
};

// Not thread-safe: one encoder per stream (an eye), used by one thread at a time.
class Encoder {
 public:
  // Null with `error` when the settings are invalid or libx264 is not available.
  static std::unique_ptr<Encoder> Create(const EncoderSettings& settings, std::string* error);
  ~Encoder();
  Encoder(const Encoder&) = delete;
  Encoder& operator=(const Encoder&) = delete;

  // Encodes `image` (CV_8UC3 BGR or CV_8UC1 grey, exactly the configured size) into `out`.
  // False with `error` on other input or an encoder error (the stream goes on: the next frame
  // is an IDR).
  bool Encode(const cv::Mat& image, EncodedFrame* out, std::string* error);
  // The next frame is an IDR (with SPS and PPS).
  void ForceIdr() { force_idr_ = true; }
  // Target and VBV maximum from the next frame on; clamped to >= 50 kbit/s.
  void SetBitrate(int bitrate_bps);
  int bitrate_bps() const { return bitrate_bps_; }
  const EncoderSettings& settings() const { return settings_; }

  struct Codec;  // libavcodec state (implementation detail)

 private:
  Encoder(const EncoderSettings& settings, std::unique_ptr<Codec> codec);

  const EncoderSettings settings_;
  std::unique_ptr<Codec> codec_;
  int bitrate_bps_;
  bool force_idr_ = false;
  int64_t next_index_ = 0;
};

}  // namespace mostar::h264
