#include "robot_server/camera/jpeg_compressor.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "common/jpeg/jpeg_decoder.h"
#include "robot_server/camera/fake_stereo_camera.h"

namespace mostar::camera {
namespace {

StereoImagePair TestPair() {
  StereoImagePair pair;
  pair.sequence = 17;
  pair.stamp = FromUnixNanos(1'700'000'000'123'456'789);
  pair.left = MakeSyntheticImage(640, 480, 5, false);
  pair.right = MakeSyntheticImage(640, 480, 5, true);
  return pair;
}

TEST(JpegEncoderTest, RoundTripKeepsTheImage) {
  const cv::Mat image = MakeSyntheticImage(320, 240, 1, false);
  JpegEncoder encoder;
  JpegDecoder decoder;
  std::vector<uint8_t> jpeg;
  std::string error;
  ASSERT_TRUE(encoder.Encode(image, {90, 1.0}, &jpeg, &error)) << error;
  ASSERT_GT(jpeg.size(), 100u);
  EXPECT_EQ(jpeg[0], 0xFF);
  EXPECT_EQ(jpeg[1], 0xD8);
  cv::Mat decoded;
  ASSERT_TRUE(decoder.Decode(jpeg, &decoded, &error)) << error;
  EXPECT_EQ(decoded.size(), image.size());
  EXPECT_EQ(decoded.type(), CV_8UC3);
  EXPECT_GT(cv::PSNR(image, decoded), 28.0);
  // Colour order survives (BGR in, BGR out): the red disc stays red.
  const cv::Vec3b centre = decoded.at<cv::Vec3b>(120, 150);
  EXPECT_GT(centre[2], 150);
  EXPECT_LT(centre[0], 100);
  EXPECT_EQ(decoder.decoded(), 1u);
}

TEST(JpegEncoderTest, LowerQualityAndScaleGiveSmallerFiles) {
  const cv::Mat image = MakeSyntheticImage(640, 480, 2, false);
  JpegEncoder encoder;
  std::string error;
  std::vector<uint8_t> high, low, half;
  ASSERT_TRUE(encoder.Encode(image, {90, 1.0}, &high, &error));
  ASSERT_TRUE(encoder.Encode(image, {40, 1.0}, &low, &error));
  ASSERT_TRUE(encoder.Encode(image, {90, 0.5}, &half, &error));
  EXPECT_LT(low.size(), high.size());
  EXPECT_LT(half.size(), high.size() * 6 / 10);
  JpegDecoder decoder;
  cv::Mat decoded;
  ASSERT_TRUE(decoder.Decode(half, &decoded, &error)) << error;
  EXPECT_EQ(decoded.size(), cv::Size(320, 240));
}

TEST(JpegEncoderTest, RejectsBadInputWithAMessage) {
  JpegEncoder encoder;
  std::vector<uint8_t> out;
  std::string error;
  EXPECT_FALSE(encoder.Encode(cv::Mat(), {80, 1.0}, &out, &error));
  EXPECT_NE(error.find("non-empty"), std::string::npos);
  EXPECT_FALSE(encoder.Encode(cv::Mat(8, 8, CV_32FC3), {80, 1.0}, &out, &error));
  EXPECT_FALSE(encoder.Encode(cv::Mat(8, 8, CV_8UC3), {0, 1.0}, &out, &error));
  EXPECT_NE(error.find("quality"), std::string::npos);
  EXPECT_FALSE(encoder.Encode(cv::Mat(8, 8, CV_8UC3), {80, 1.5}, &out, &error));
  EXPECT_NE(error.find("scale"), std::string::npos);
  // Still usable afterwards.
  EXPECT_TRUE(encoder.Encode(cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3)), {80, 1.0}, &out, &error));
}

TEST(JpegCompressorTest, CompressesBothEyesWithTheSharedStamp) {
  JpegCompressor compressor;
  CompressedStereoPair out;
  std::string error;
  const StereoImagePair pair = TestPair();
  ASSERT_TRUE(compressor.Compress(pair, {75, 1.0}, &out, &error)) << error;
  EXPECT_EQ(out.sequence, 17u);
  EXPECT_EQ(out.left.stamp, pair.stamp);
  EXPECT_EQ(out.right.stamp, pair.stamp);
  EXPECT_EQ(out.left.frame_id, "camera_left");
  EXPECT_EQ(out.right.frame_id, "camera_right");
  EXPECT_EQ(out.left.format, "jpeg");
  JpegDecoder decoder;
  cv::Mat left, right;
  ASSERT_TRUE(decoder.Decode(out.left.data, &left, &error)) << error;
  ASSERT_TRUE(decoder.Decode(out.right.data, &right, &error)) << error;
  EXPECT_GT(cv::PSNR(left, pair.left), 25.0);
  EXPECT_GT(cv::PSNR(right, pair.right), 25.0);
  EXPECT_LT(cv::PSNR(left, pair.right), cv::PSNR(left, pair.left));  // eyes not swapped
}

TEST(JpegCompressorTest, ParallelAndSerialProduceTheSameBytes) {
  JpegCompressor parallel(true);
  JpegCompressor serial(false);
  const StereoImagePair pair = TestPair();
  CompressedStereoPair a, b;
  std::string error;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(parallel.Compress(pair, {60, 0.75}, &a, &error)) << error;
    ASSERT_TRUE(serial.Compress(pair, {60, 0.75}, &b, &error)) << error;
    EXPECT_EQ(a.left.data, b.left.data);
    EXPECT_EQ(a.right.data, b.right.data);
  }
}

TEST(JpegCompressorTest, ReportsWhichEyeFailed) {
  JpegCompressor compressor;
  StereoImagePair pair = TestPair();
  pair.right = cv::Mat();
  CompressedStereoPair out;
  std::string error;
  EXPECT_FALSE(compressor.Compress(pair, {75, 1.0}, &out, &error));
  EXPECT_NE(error.find("right eye"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::camera
