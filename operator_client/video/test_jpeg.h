// JPEG data for the video tests: real images, and images whose header lies about their size.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

namespace mostar::client::testing {

// A grey `width` x `height` BGR image of `value`, JPEG-encoded.
inline std::vector<uint8_t> EncodeJpeg(int width, int height, int value) {
  const cv::Mat image(height, width, CV_8UC3, cv::Scalar(value, value, value));
  std::vector<uint8_t> out;
  cv::imencode(".jpg", image, out);
  return out;
}

// `jpeg` with the frame header (SOF0) declaring `width` x `height` instead; the scan data stays
// that of the real, small image.
inline std::vector<uint8_t> WithDeclaredSize(std::vector<uint8_t> jpeg, int width, int height) {
  for (size_t i = 0; i + 8 < jpeg.size(); ++i) {
    if (jpeg[i] == 0xFF && jpeg[i + 1] == 0xC0) {       // FF C0, length (2), precision (1), then
      jpeg[i + 5] = static_cast<uint8_t>(height >> 8);  // height and width, big endian
      jpeg[i + 6] = static_cast<uint8_t>(height & 0xFF);
      jpeg[i + 7] = static_cast<uint8_t>(width >> 8);
      jpeg[i + 8] = static_cast<uint8_t>(width & 0xFF);
      break;
    }
  }
  return jpeg;
}

}  // namespace mostar::client::testing
