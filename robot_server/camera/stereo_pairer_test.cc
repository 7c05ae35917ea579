#include "robot_server/camera/stereo_pairer.h"

#include <gtest/gtest.h>

namespace mostar::camera {
namespace {

using std::chrono::milliseconds;

const Time kT0 = FromUnixNanos(1'700'000'000'000'000'000);

TimedImage Frame(Time stamp, int value) {
  return {stamp, cv::Mat(2, 2, CV_8UC3, cv::Scalar::all(value))};
}

int Value(const cv::Mat& image) { return image.at<cv::Vec3b>(0, 0)[0]; }

TEST(StereoPairerTest, PairsFramesWithEqualStamps) {
  StereoPairer pairer;
  pairer.AddLeft(Frame(kT0, 1));
  EXPECT_FALSE(pairer.PopPair().has_value());
  pairer.AddRight(Frame(kT0, 2));
  const auto pair = pairer.PopPair();
  ASSERT_TRUE(pair.has_value());
  EXPECT_EQ(pair->stamp, kT0);
  EXPECT_EQ(pair->sequence, 0u);
  EXPECT_EQ(Value(pair->left), 1);
  EXPECT_EQ(Value(pair->right), 2);
  EXPECT_EQ(pairer.stats().pairs, 1u);
}

TEST(StereoPairerTest, PairStampIsTheMidpointAndSkewIsLeftMinusRight) {
  StereoPairer pairer;
  pairer.AddLeft(Frame(kT0 + milliseconds(4), 1));
  pairer.AddRight(Frame(kT0, 2));
  const auto pair = pairer.PopPair();
  ASSERT_TRUE(pair.has_value());
  EXPECT_EQ(pair->stamp, kT0 + milliseconds(2));
  EXPECT_EQ(pairer.stats().last_skew, milliseconds(4));
}

TEST(StereoPairerTest, DropsAFrameWhosePartnerWasLost) {
  StereoPairer pairer;  // 10 ms tolerance
  // 30 Hz; the right frame at t=33 ms is lost.
  pairer.AddLeft(Frame(kT0, 1));
  pairer.AddRight(Frame(kT0 + milliseconds(1), 1));
  pairer.AddLeft(Frame(kT0 + milliseconds(33), 2));
  pairer.AddLeft(Frame(kT0 + milliseconds(66), 3));
  pairer.AddRight(Frame(kT0 + milliseconds(67), 3));
  std::vector<int> values;
  while (auto pair = pairer.PopPair()) {
    EXPECT_EQ(Value(pair->left), Value(pair->right));
    values.push_back(Value(pair->left));
  }
  EXPECT_EQ(values, (std::vector<int>{1, 3}));
  EXPECT_EQ(pairer.stats().dropped_left, 1u);
  EXPECT_EQ(pairer.stats().dropped_right, 0u);
}

TEST(StereoPairerTest, PrefersTheNearestPartner) {
  StereoPairerOptions options;
  options.max_skew = milliseconds(20);
  StereoPairer pairer(options);
  pairer.AddRight(Frame(kT0, 1));
  pairer.AddRight(Frame(kT0 + milliseconds(15), 2));
  pairer.AddLeft(Frame(kT0 + milliseconds(14), 9));  // 14 ms from the first, 1 ms from the second
  const auto pair = pairer.PopPair();
  ASSERT_TRUE(pair.has_value());
  EXPECT_EQ(Value(pair->right), 2);
  EXPECT_EQ(pairer.stats().dropped_right, 1u);
}

TEST(StereoPairerTest, BoundsPendingFramesWhenOneEyeStalls) {
  StereoPairerOptions options;
  options.max_pending = 3;
  StereoPairer pairer(options);
  for (int i = 0; i < 10; ++i) pairer.AddLeft(Frame(kT0 + milliseconds(33 * i), i));
  EXPECT_EQ(pairer.pending_left(), 3u);
  EXPECT_EQ(pairer.stats().dropped_left, 7u);
  EXPECT_FALSE(pairer.PopPair().has_value());
}

TEST(StereoPairerTest, RejectsOutOfOrderFrames) {
  StereoPairer pairer;
  pairer.AddLeft(Frame(kT0 + milliseconds(50), 1));
  pairer.AddLeft(Frame(kT0, 2));
  EXPECT_EQ(pairer.stats().dropped_left, 1u);
  EXPECT_EQ(pairer.pending_left(), 1u);
}

TEST(StereoPairerTest, MeasuresDriftOfFreeRunningCameras) {
  StereoPairer pairer;
  // The right camera runs slightly slow: skew grows by 0.1 ms per frame at 30 Hz = 3 ms/s.
  for (int i = 0; i < 60; ++i) {
    const Time left = kT0 + FromSeconds(i / 30.0);
    pairer.AddLeft(Frame(left, 1));
    pairer.AddRight(Frame(left - FromMilliseconds(0.1 * i), 1));
    ASSERT_TRUE(pairer.PopPair().has_value());
  }
  EXPECT_NEAR(pairer.stats().drift_ns_per_s, 3e6, 1e4);
  EXPECT_NEAR(ToSeconds(pairer.stats().last_skew), 5.9e-3, 1e-6);
  EXPECT_GT(pairer.stats().mean_skew, milliseconds(2));
}

TEST(StereoPairerTest, OptionsValidation) {
  std::string error;
  StereoPairerOptions options;
  EXPECT_TRUE(options.IsValid(&error));
  options.max_skew = Duration::zero();
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_skew"), std::string::npos);
}

}  // namespace
}  // namespace mostar::camera
