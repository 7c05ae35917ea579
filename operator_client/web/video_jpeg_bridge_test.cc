#include "operator_client/web/video_jpeg_bridge.h"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <vector>

#include "common/h264/h264_encoder.h"

namespace mostar::web {
namespace {

TEST(VideoJpegBridgeTest, DecodedH264PairsReachTheSinkAsJpeg) {
  std::mutex mutex;
  std::vector<CompressedStereoPair> pairs;
  VideoJpegBridge bridge([&](CompressedStereoPair pair) {
    std::lock_guard<std::mutex> lock(mutex);
    pairs.push_back(std::move(pair));
  });
  h264::EncoderSettings settings;
  settings.width_px = 160;
  settings.height_px = 120;
  std::string error;
  auto left = h264::Encoder::Create(settings, &error);
  auto right = h264::Encoder::Create(settings, &error);
  ASSERT_NE(right, nullptr) << error;
  const Time t0 = FromUnixNanos(1'600'000'000'000'000'000);
  for (uint64_t n = 1; n <= 3; ++n) {
    cv::Mat l(120, 160, CV_8UC3, cv::Scalar(20, 20, 20));
    cv::Mat r(120, 160, CV_8UC3, cv::Scalar(230, 230, 230));
    h264::EncodedFrame lf;
    h264::EncodedFrame rf;
    ASSERT_TRUE(left->Encode(l, &lf, &error)) << error;
    ASSERT_TRUE(right->Encode(r, &rf, &error)) << error;
    StereoVideoFrame frame;
    frame.sequence = n;
    frame.stamp = t0 + std::chrono::milliseconds(33 * n);
    frame.left = lf.data;
    frame.right = rf.data;
    bridge.Push(frame);
    // Each pair is encoded before the next one comes (the bridge sends only the newest).
    for (int i = 0; i < 2500; ++i) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (pairs.size() >= n) break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs.back().left.stamp, t0 + std::chrono::milliseconds(99));
  EXPECT_EQ(pairs.back().left.format, "jpeg");
  const cv::Mat l = cv::imdecode(pairs.back().left.data, cv::IMREAD_GRAYSCALE);
  const cv::Mat r = cv::imdecode(pairs.back().right.data, cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(l.cols, 160);
  EXPECT_LT(l.at<uint8_t>(60, 80), 50);
  EXPECT_GT(r.at<uint8_t>(60, 80), 200);
  EXPECT_EQ(bridge.Stats().pairs_encoded, 3u);
}

}  // namespace
}  // namespace mostar::web
