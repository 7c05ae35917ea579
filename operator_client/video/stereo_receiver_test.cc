#include "operator_client/video/stereo_receiver.h"

#include <gtest/gtest.h>

#include <chrono>
#include <opencv2/imgcodecs.hpp>
#include <thread>

namespace mostar::client {
namespace {

CompressedImage Jpeg(Time stamp, int value) {
  cv::Mat image(48, 64, CV_8UC3, cv::Scalar(value, value, value));
  CompressedImage out;
  out.stamp = stamp;
  out.format = "jpeg";
  cv::imencode(".jpg", image, out.data);
  return out;
}

template <class Predicate>
bool WaitFor(Predicate predicate) {
  for (int i = 0; i < 500 && !predicate(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return predicate();
}

TEST(StereoReceiverTest, PairsEyesByStampAndDecodes) {
  StereoReceiver receiver;
  const Time t = FromUnixNanos(1'000'000'000);
  receiver.Push(Eye::kLeft, Jpeg(t, 40));
  EXPECT_FALSE(receiver.Latest().has_value());
  receiver.Push(Eye::kRight, Jpeg(t, 200));
  ASSERT_TRUE(WaitFor([&] { return receiver.Latest().has_value(); }));
  const DecodedStereoPair pair = *receiver.Latest();
  EXPECT_EQ(pair.stamp, t);
  EXPECT_EQ(pair.left.cols, 64);
  EXPECT_LT(pair.left.at<cv::Vec3b>(10, 10)[0], 60);
  EXPECT_GT(pair.right.at<cv::Vec3b>(10, 10)[0], 180);
}

TEST(StereoReceiverTest, BrokenJpegIsCountedAndLaterPairsStillDecode) {
  StereoReceiver receiver;
  CompressedImage broken = Jpeg(FromUnixNanos(1), 10);
  broken.data.resize(20);
  receiver.Push(Eye::kLeft, broken);
  receiver.Push(Eye::kRight, Jpeg(FromUnixNanos(1), 10));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().broken_images == 1; }));
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(2), 10));
  receiver.Push(Eye::kRight, Jpeg(FromUnixNanos(2), 10));
  ASSERT_TRUE(WaitFor([&] { return receiver.Latest().has_value(); }));
  EXPECT_EQ(receiver.Latest()->stamp, FromUnixNanos(2));
  EXPECT_EQ(receiver.Stats().pairs_decoded, 1u);
}

TEST(StereoReceiverTest, UnpairedEyesAreDroppedAndCounted) {
  StereoReceiver receiver;
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(1), 10));  // partner never comes
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(5), 10));
  receiver.Push(Eye::kRight, Jpeg(FromUnixNanos(5), 10));
  ASSERT_TRUE(WaitFor([&] { return receiver.Latest().has_value(); }));
  EXPECT_EQ(receiver.Stats().unpaired_dropped, 1u);
  EXPECT_EQ(receiver.Stats().images, 3u);
}

TEST(StereoReceiverTest, PairCompletedAfterANewerOneIsDroppedAndCounted) {
  StereoReceiver receiver;
  // Pair 1 and pair 2 in flight on different writers; pair 2 completes first.
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(2), 200));
  receiver.Push(Eye::kRight, Jpeg(FromUnixNanos(2), 200));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 1; }));
  receiver.Push(Eye::kRight, Jpeg(FromUnixNanos(1), 10));
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(1), 10));
  EXPECT_EQ(receiver.Stats().late_dropped, 1u);
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(3), 90));
  receiver.Push(Eye::kRight, Jpeg(FromUnixNanos(3), 90));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 2; }));
  EXPECT_EQ(receiver.Latest()->stamp, FromUnixNanos(3));
  EXPECT_EQ(receiver.Stats().late_dropped, 1u);
  EXPECT_EQ(receiver.Stats().unpaired_dropped, 0u);
}

}  // namespace
}  // namespace mostar::client
