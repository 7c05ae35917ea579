#include "operator_client/web/video_jpeg_bridge.h"

#include <algorithm>
#include <chrono>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "common/log/log.h"

namespace mostar::web {

VideoJpegBridge::VideoJpegBridge(Sink sink, int quality, const Clock* clock)
    : sink_(std::move(sink)), quality_(std::clamp(quality, 1, 100)), receiver_(clock) {
  thread_ = std::thread([this] { Loop(); });
}

VideoJpegBridge::~VideoJpegBridge() {
  stop_ = true;
  thread_.join();
}

void VideoJpegBridge::Loop() {
  uint64_t last = 0;
  const std::vector<int> params = {cv::IMWRITE_JPEG_QUALITY, quality_};
  while (!stop_.load()) {
    const std::optional<client::DecodedStereoPair> decoded = receiver_.Latest();
    if (!decoded || decoded->sequence == last) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      continue;
    }
    last = decoded->sequence;
    CompressedStereoPair pair;
    pair.sequence = decoded->sequence;
    for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
      CompressedImage& image = eye == Eye::kLeft ? pair.left : pair.right;
      image.stamp = decoded->stamp;
      image.frame_id = eye == Eye::kLeft ? "camera_left" : "camera_right";
      image.format = "jpeg";
      const cv::Mat& pixels = eye == Eye::kLeft ? decoded->left : decoded->right;
      if (!pixels.empty() && !cv::imencode(".jpg", pixels, image.data, params)) {
        MOSTAR_LOG_EVERY_SEC(WARNING, 5) << "JPEG encoding of a decoded H.264 pair failed";
        image.data.clear();
      }
    }
    pair.encoded = decoded->stamp;
    ++encoded_;
    sink_(std::move(pair));
  }
}

VideoJpegBridgeStats VideoJpegBridge::Stats() const {
  VideoJpegBridgeStats stats;
  stats.pairs_encoded = encoded_.load();
  stats.decoder = receiver_.Stats();
  return stats;
}

}  // namespace mostar::web
