#include "common/jpeg/jpeg_decoder.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace mostar {
namespace {

// Four flat quadrants: blue, green, red, white (BGR), JPEG q95.
std::vector<uint8_t> Quadrants(int width, int height) {
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  image(cv::Rect(0, 0, width / 2, height / 2)).setTo(cv::Scalar(255, 0, 0));
  image(cv::Rect(width / 2, 0, width - width / 2, height / 2)).setTo(cv::Scalar(0, 255, 0));
  image(cv::Rect(0, height / 2, width / 2, height - height / 2)).setTo(cv::Scalar(0, 0, 255));
  std::vector<uint8_t> out;
  cv::imencode(".jpg", image, out, {cv::IMWRITE_JPEG_QUALITY, 95});
  return out;
}

TEST(DecodeScaleDenominatorTest, TheSmallestScaleThatCoversTheTarget) {
  EXPECT_EQ(DecodeScaleDenominator(1280, 960, 0, 0), 1);        // no target: full size
  EXPECT_EQ(DecodeScaleDenominator(1280, 960, 1920, 1080), 1);  // bigger than the image
  EXPECT_EQ(DecodeScaleDenominator(1280, 960, 1280, 960), 1);
  EXPECT_EQ(DecodeScaleDenominator(1280, 960, 1279, 959), 1);  // 640 would not cover it
  EXPECT_EQ(DecodeScaleDenominator(1280, 960, 640, 480), 2);
  EXPECT_EQ(DecodeScaleDenominator(1280, 960, 640, 481), 1);  // both directions covered
  EXPECT_EQ(DecodeScaleDenominator(1280, 960, 320, 240), 4);
  EXPECT_EQ(DecodeScaleDenominator(1280, 960, 100, 50), 8);  // 1/8 at most
  EXPECT_EQ(DecodeScaleDenominator(641, 481, 320, 240), 2);  // ceil: 321 x 241
}

TEST(JpegDecoderTest, DecodesAtEachDctScaleWithTheScaledSizeAndContent) {
  const std::vector<uint8_t> jpeg = Quadrants(1280, 960);
  JpegDecoder decoder;
  for (int d : {1, 2, 4, 8}) {
    cv::Mat bgr;
    std::string error;
    ASSERT_TRUE(decoder.Decode(jpeg.data(), jpeg.size(), d, &bgr, &error)) << error;
    ASSERT_EQ(bgr.type(), CV_8UC3);
    EXPECT_EQ(bgr.cols, 1280 / d);
    EXPECT_EQ(bgr.rows, 960 / d);
    // Quadrant centres keep their colours (BGR order out).
    const auto at = [&](double fx, double fy) {
      return bgr.at<cv::Vec3b>(static_cast<int>(fy * bgr.rows), static_cast<int>(fx * bgr.cols));
    };
    EXPECT_GT(at(0.25, 0.25)[0], 230) << "1/" << d;
    EXPECT_LT(at(0.25, 0.25)[2], 25) << "1/" << d;
    EXPECT_GT(at(0.75, 0.25)[1], 230) << "1/" << d;
    EXPECT_GT(at(0.25, 0.75)[2], 230) << "1/" << d;
    EXPECT_LT(at(0.25, 0.75)[0], 25) << "1/" << d;
  }
}

TEST(JpegDecoderTest, GreyIsTheLumaOfTheColourDecode) {
  const std::vector<uint8_t> jpeg = Quadrants(640, 480);
  JpegDecoder decoder;
  cv::Mat bgr, grey, expected;
  std::string error;
  ASSERT_TRUE(decoder.Decode(jpeg.data(), jpeg.size(), 2, &bgr, &error)) << error;
  ASSERT_TRUE(decoder.Decode(jpeg.data(), jpeg.size(), 2, &grey, &error, JpegPixels::kGrey))
      << error;
  ASSERT_EQ(grey.type(), CV_8UC1);
  ASSERT_EQ(grey.size(), bgr.size());
  cv::cvtColor(bgr, expected, cv::COLOR_BGR2GRAY);
  double worst = 0;
  cv::minMaxLoc(cv::abs(grey - expected) + cv::abs(expected - grey), nullptr, &worst);
  EXPECT_LE(worst, 3) << "grey differs from the colour decode's luma";
  EXPECT_LT(grey.at<uint8_t>(60, 80), 60);     // blue quadrant: dark
  EXPECT_GT(grey.at<uint8_t>(180, 240), 230);  // white quadrant
  EXPECT_EQ(decoder.decoded(), 2u);
}

TEST(JpegDecoderTest, OddSizesRoundUp) {
  const std::vector<uint8_t> jpeg = Quadrants(641, 481);
  JpegDecoder decoder;
  cv::Mat bgr;
  std::string error;
  ASSERT_TRUE(decoder.Decode(jpeg.data(), jpeg.size(), 4, &bgr, &error)) << error;
  EXPECT_EQ(bgr.cols, ScaledJpegSize(641, 4));
  EXPECT_EQ(bgr.rows, ScaledJpegSize(481, 4));
  EXPECT_EQ(bgr.cols, 161);
}

TEST(JpegDecoderTest, BrokenJpegIsAnErrorCountedAndTheDecoderStillWorksAfterwards) {
  const std::vector<uint8_t> jpeg = Quadrants(320, 240);
  JpegDecoder decoder;
  cv::Mat bgr;
  std::string error;

  const std::vector<uint8_t> truncated(jpeg.begin(), jpeg.begin() + jpeg.size() / 2);
  EXPECT_FALSE(decoder.Decode(truncated.data(), truncated.size(), 2, &bgr, &error));
  EXPECT_EQ(error.rfind("broken jpeg: ", 0), 0u) << error;

  const std::vector<uint8_t> garbage(100, 0x55);
  EXPECT_FALSE(decoder.Decode(garbage, &bgr, &error));
  EXPECT_NE(error.find("start-of-image"), std::string::npos) << error;

  EXPECT_FALSE(decoder.Decode(nullptr, 0, 1, &bgr, nullptr));  // no message asked for

  const std::vector<uint8_t> header_only(jpeg.begin(), jpeg.begin() + 20);
  EXPECT_FALSE(decoder.Decode(header_only, &bgr, &error));

  std::vector<uint8_t> corrupted = jpeg;
  for (size_t i = corrupted.size() / 3; i < corrupted.size() / 3 + 64; ++i) corrupted[i] = 0xFF;
  EXPECT_FALSE(decoder.Decode(corrupted, &bgr, &error));

  EXPECT_EQ(decoder.broken(), 5u);
  EXPECT_EQ(decoder.decoded(), 0u);
  ASSERT_TRUE(decoder.Decode(jpeg, &bgr, &error)) << error;
  EXPECT_EQ(bgr.cols, 320);
  EXPECT_EQ(decoder.decoded(), 1u);
}

}  // namespace
}  // namespace mostar
