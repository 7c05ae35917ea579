// JPEG to BGR8 with libjpeg-turbo, for both sides: the robot's round-trip checks and the
// client's display path. libjpeg-turbo's DCT scaling decodes an image shown smaller than it was
// sent at 1/2, 1/4 or 1/8 of its size, which costs a fraction of a full decode and a resize.
// Any libjpeg warning (corrupt or truncated data) counts as an error: a damaged image is
// reported and counted, never shown half grey.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

namespace mostar {

// The largest denominator d in {1, 2, 4, 8} such that an image of `width_px` x `height_px`
// decoded at 1/d still covers `target_width_px` x `target_height_px` in both directions
// (libjpeg's scaled size: ceil(size / d)). A non-positive target means full size (1).
int DecodeScaleDenominator(int width_px, int height_px, int target_width_px, int target_height_px);

// The size libjpeg gives an image of `size_px` decoded at 1/`denominator`: ceil(size / d).
inline int ScaledJpegSize(int size_px, int denominator) {
  return (size_px + denominator - 1) / denominator;
}

// What a decode produces: BGR8 (CV_8UC3) or intensity only (CV_8UC1, libjpeg's own luma: no
// colour conversion pass, for edge processing).
enum class JpegPixels { kBgr, kGrey };

// Keeps its libjpeg state between calls. Not thread-safe.
class JpegDecoder {
 public:
  JpegDecoder();
  ~JpegDecoder();
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;

  // Decodes `data` at 1/`denominator` of its size (1, 2, 4 or 8; checked) into `image`
  // (ScaledJpegSize() of the declared size, `pixels` decides the type; replaced). False with a
  // message starting "broken jpeg: " on any libjpeg error or warning; `error` may be null.
  bool Decode(const uint8_t* data, size_t size, int denominator, cv::Mat* image, std::string* error,
              JpegPixels pixels = JpegPixels::kBgr);
  // Full size.
  bool Decode(const std::vector<uint8_t>& data, cv::Mat* bgr, std::string* error) {
    return Decode(data.data(), data.size(), 1, bgr, error);
  }

  uint64_t decoded() const { return decoded_; }  // successful calls
  uint64_t broken() const { return broken_; }    // failed calls

  struct State;  // libjpeg state (implementation detail)

 private:
  bool Fail(const std::string& message, std::string* error);

  std::unique_ptr<State> state_;
  uint64_t decoded_ = 0;
  uint64_t broken_ = 0;
};

}  // namespace mostar
