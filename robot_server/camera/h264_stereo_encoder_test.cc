#include "robot_server/camera/h264_stereo_encoder.h"

#include <gtest/gtest.h>

#include "common/h264/h264_decoder.h"
#include "robot_server/camera/fake_stereo_camera.h"

namespace mostar::camera {
namespace {

StereoImagePair Pair(int width_px, int height_px, uint64_t n) {
  StereoImagePair pair;
  pair.sequence = n;
  pair.stamp = FromUnixNanos(1'700'000'000'000'000'000 + static_cast<int64_t>(n) * 33'000'000);
  pair.left = MakeSyntheticImage(width_px, height_px, n, false);
  pair.right = MakeSyntheticImage(width_px, height_px, n, true);
  return pair;
}

class H264StereoEncoderTest : public ::testing::TestWithParam<bool> {};  // parallel or not

TEST_P(H264StereoEncoderTest, BothEyesDecodeAndAdvanceTogether) {
  H264StereoEncoder encoder(H264StreamOptions(), 30, GetParam());
  std::string error;
  auto left = h264::Decoder::Create(&error);
  auto right = h264::Decoder::Create(&error);
  ASSERT_NE(right, nullptr) << error;
  for (uint64_t n = 0; n < 10; ++n) {
    if (n == 6) encoder.ForceIdr();
    StereoVideoFrame frame;
    ASSERT_TRUE(encoder.Encode(Pair(320, 240, n), 2e6, &frame, &error)) << error;
    EXPECT_EQ(frame.sequence, n + 1);
    EXPECT_EQ(frame.idr, n == 0 || n == 6) << n;
    EXPECT_EQ(frame.width_px, 320);
    cv::Mat l;
    cv::Mat r;
    EXPECT_EQ(left->Decode(frame.left.data(), frame.left.size(), frame.sequence, &l, &error),
              h264::DecodeStatus::kPicture);
    EXPECT_EQ(right->Decode(frame.right.data(), frame.right.size(), frame.sequence, &r, &error),
              h264::DecodeStatus::kPicture);
    EXPECT_EQ(l.cols, 320);
    EXPECT_EQ(r.rows, 240);
  }
  EXPECT_EQ(encoder.bitrate_bps(), 2'000'000);
  EXPECT_EQ(encoder.restarts(), 1u);
}

TEST_P(H264StereoEncoderTest, ASizeChangeRestartsWithAnIdrAndBadInputUsesUpANumber) {
  H264StereoEncoder encoder(H264StreamOptions(), 30, GetParam());
  std::string error;
  StereoVideoFrame frame;
  ASSERT_TRUE(encoder.Encode(Pair(320, 240, 0), 0, &frame, &error)) << error;
  ASSERT_TRUE(encoder.Encode(Pair(320, 240, 1), 0, &frame, &error)) << error;
  EXPECT_FALSE(frame.idr);
  EXPECT_EQ(encoder.bitrate_bps(), 16'000'000);  // unlimited: the configured rate
  ASSERT_TRUE(encoder.Encode(Pair(160, 120, 2), 0, &frame, &error)) << error;
  EXPECT_TRUE(frame.idr);
  EXPECT_EQ(frame.width_px, 160);
  EXPECT_EQ(encoder.restarts(), 2u);
  StereoImagePair odd = Pair(160, 120, 3);
  odd.right = odd.right.colRange(0, 80).clone();
  EXPECT_FALSE(encoder.Encode(odd, 0, &frame, &error));
  EXPECT_NE(error.find("same"), std::string::npos) << error;
  ASSERT_TRUE(encoder.Encode(Pair(160, 120, 4), 0, &frame, &error)) << error;
  EXPECT_EQ(frame.sequence, 5u);  // a viewer sees the failed pair as a gap...
  EXPECT_TRUE(frame.idr);         // ...and can decode again at once
}

INSTANTIATE_TEST_SUITE_P(Threads, H264StereoEncoderTest, ::testing::Bool());

}  // namespace
}  // namespace mostar::camera
