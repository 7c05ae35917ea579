#include "operator_client/vision/edge_detector.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace mostar::vision {
namespace {

TEST(EdgeDetectorOptionsTest, DefaultsAreValid) {
  std::string error;
  EXPECT_TRUE(EdgeDetectorOptions{}.IsValid(&error)) << error;
}

TEST(EdgeDetectorOptionsTest, NamesTheViolatedConstraint) {
  std::string error;
  EdgeDetectorOptions options;
  options.low_threshold = 200;
  options.high_threshold = 100;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("low_threshold must be < high_threshold"), std::string::npos) << error;

  options = EdgeDetectorOptions{};
  options.canny_threshold2 = options.canny_threshold1 - 1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("canny_threshold2"), std::string::npos) << error;

  options = EdgeDetectorOptions{};
  options.canny_aperture_px = 4;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("canny_aperture_px"), std::string::npos) << error;
}

TEST(StretchGreyTest, ClampsOutsideTheThresholdsAndIsLinearBetween) {
  EXPECT_EQ(StretchGrey(0, 50, 150), 0);
  EXPECT_EQ(StretchGrey(50, 50, 150), 0);
  EXPECT_EQ(StretchGrey(100, 50, 150), 128);  // 127.5 rounds up
  EXPECT_EQ(StretchGrey(150, 50, 150), 255);
  EXPECT_EQ(StretchGrey(255, 50, 150), 255);
  for (int g = 51; g < 150; ++g) {
    EXPECT_LE(StretchGrey(g - 1, 50, 150), StretchGrey(g, 50, 150));
  }
}

TEST(EdgeDetectorTest, RejectsUnsupportedImagesWithAMessage) {
  const EdgeDetector detector(EdgeDetectorOptions{});
  EdgeImages out;
  std::string error;
  EXPECT_FALSE(detector.Detect(cv::Mat(), &out, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(detector.Detect(cv::Mat(10, 10, CV_16UC1, cv::Scalar(0)), &out, &error));
  EXPECT_NE(error.find("8-bit"), std::string::npos) << error;
  EXPECT_TRUE(out.edges.empty());
}

TEST(EdgeDetectorTest, FindsAStepAndNothingInFlatAreas) {
  cv::Mat image(120, 160, CV_8UC3, cv::Scalar(40, 40, 40));
  image.rowRange(60, 120).setTo(cv::Scalar(180, 180, 180));
  const EdgeDetector detector(EdgeDetectorOptions{});
  EdgeImages out;
  std::string error;
  ASSERT_TRUE(detector.Detect(image, &out, &error)) << error;
  ASSERT_EQ(out.edges.type(), CV_8UC1);
  ASSERT_EQ(out.stretched_grey.size(), image.size());
  EXPECT_EQ(out.stretched_grey.at<uint8_t>(10, 10), 0);  // 40 < lowTh
  for (int col = 5; col < 155; ++col) {
    const int hits = (out.edges.at<uint8_t>(59, col) != 0) + (out.edges.at<uint8_t>(60, col) != 0);
    EXPECT_GE(hits, 1) << "column " << col;
  }
  EXPECT_EQ(cv::countNonZero(out.edges.rowRange(0, 55)), 0);
  EXPECT_EQ(cv::countNonZero(out.edges.rowRange(65, 120)), 0);
}

// The open room's brown crate on its grey-blue floor: nearly the same grey (136 and 144), a
// different colour. Grey edges alone find nothing; colour edges find the boundary, and a grey
// image has no colour to add.
TEST(EdgeDetectorTest, ColourEdgesFindABaseAsGreyAsTheFloor) {
  cv::Mat image(120, 160, CV_8UC3, cv::Scalar(150, 146, 140));  // BGR: the floor
  image.rowRange(0, 60).setTo(cv::Scalar(80, 130, 170));        // the crate
  EdgeDetectorOptions grey_only;
  grey_only.colour_edges = false;
  EdgeImages out;
  std::string error;
  ASSERT_TRUE(EdgeDetector(grey_only).Detect(image, &out, &error)) << error;
  EXPECT_EQ(cv::countNonZero(out.edges), 0);
  ASSERT_TRUE(EdgeDetector(EdgeDetectorOptions{}).Detect(image, &out, &error)) << error;
  for (int col = 5; col < 155; ++col) {
    const int hits = (out.edges.at<uint8_t>(59, col) != 0) + (out.edges.at<uint8_t>(60, col) != 0);
    EXPECT_GE(hits, 1) << "column " << col;
  }
  EXPECT_EQ(cv::countNonZero(out.edges.rowRange(0, 55)), 0);
  EXPECT_EQ(cv::countNonZero(out.edges.rowRange(65, 120)), 0);
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  ASSERT_TRUE(EdgeDetector(EdgeDetectorOptions{}).Detect(grey, &out, &error)) << error;
  EXPECT_EQ(cv::countNonZero(out.edges), 0);
}

TEST(EdgeDetectorTest, StretchingSuppressesAFaintPatternAboveHighThreshold) {
  // A bright floor with tiles of grey 200 and 240, both above highTh.
  cv::Mat grey(100, 100, CV_8UC1, cv::Scalar(200));
  for (int r = 0; r < 100; r += 20) grey.rowRange(r, r + 10).setTo(240);
  EdgeDetectorOptions options;
  options.high_threshold = 195;
  const EdgeDetector detector(options);
  EdgeImages out;
  std::string error;
  ASSERT_TRUE(detector.Detect(grey, &out, &error)) << error;
  EXPECT_EQ(cv::countNonZero(out.edges), 0);

  options.high_threshold = 250;  // without suppression the tiles give edges
  ASSERT_TRUE(EdgeDetector(options).Detect(grey, &out, &error)) << error;
  EXPECT_GT(cv::countNonZero(out.edges), 0);
}

TEST(EdgeDetectorTest, ProcessesOnlyTheRowsFromFirstRow) {
  cv::Mat image(120, 160, CV_8UC3, cv::Scalar(40, 40, 40));
  image.colRange(80, 160).setTo(cv::Scalar(220, 220, 220));  // a vertical step, all rows
  const EdgeDetector detector{EdgeDetectorOptions{}};
  EdgeImages full, band;
  std::string error;
  ASSERT_TRUE(detector.Detect(image, &full, &error)) << error;
  ASSERT_TRUE(detector.Detect(image, &band, &error, 50)) << error;
  ASSERT_EQ(band.edges.size(), image.size());
  EXPECT_EQ(cv::countNonZero(band.edges.rowRange(0, 50)), 0);
  EXPECT_EQ(cv::countNonZero(band.stretched_grey.rowRange(0, 50)), 0);
  EXPECT_EQ(cv::countNonZero(band.edges.rowRange(52, 118) != full.edges.rowRange(52, 118)), 0);
  EXPECT_EQ(cv::countNonZero(band.stretched_grey.rowRange(50, 120) !=
                             full.stretched_grey.rowRange(50, 120)),
            0);
  // Beyond the image: nothing processed, no failure.
  ASSERT_TRUE(detector.Detect(image, &band, &error, 500)) << error;
  EXPECT_EQ(cv::countNonZero(band.edges), 0);
}

}  // namespace
}  // namespace mostar::vision
