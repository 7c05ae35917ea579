// JPEG to BGR8 with libjpeg-turbo's DCT scaling: an image shown smaller than it was sent is
// decoded at 1/2, 1/4 or 1/8 of its size, which costs a fraction of a full decode and a resize.
// Any libjpeg warning (corrupt or truncated data) counts as an error: a damaged image is
// reported, never shown half grey.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>

namespace mostar::client {

// The largest denominator d in {1, 2, 4, 8} such that an image of `width_px` x `height_px`
// decoded at 1/d still covers `target_width_px` x `target_height_px` in both directions
// (libjpeg's scaled size: ceil(size / d)). A non-positive target means full size (1).
int DecodeScaleDenominator(int width_px, int height_px, int target_width_px, int target_height_px);

// The size libjpeg gives an image of `size_px` decoded at 1/`denominator`: ceil(size / d).
inline int ScaledJpegSize(int size_px, int denominator) {
  return (size_px + denominator - 1) / denominator;
}

// Keeps its libjpeg state between calls. Not thread-safe.
class JpegDecoder {
 public:
  JpegDecoder();
  ~JpegDecoder();
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;

  // Decodes `data` at 1/`denominator` of its size (1, 2, 4 or 8; asserted) into `bgr`
  // (CV_8UC3, ScaledJpegSize() of the declared size; replaced). False with libjpeg's message
  // on any error or warning.
  bool Decode(const uint8_t* data, size_t size, int denominator, cv::Mat* bgr, std::string* error);

  struct State;  // libjpeg state (implementation detail)

 private:
  std::unique_ptr<State> state_;
};

}  // namespace mostar::client
