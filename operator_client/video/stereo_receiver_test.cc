#include "operator_client/video/stereo_receiver.h"

#include <gtest/gtest.h>

#include <chrono>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "common/time/fake_clock.h"
#include "operator_client/video/test_jpeg.h"

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

TEST(StereoReceiverTest, EachDecodedPairWakesTheRenderLoopAndCarriesItsDecodeStart) {
  StereoReceiver receiver;
  WakeSignal wake;
  receiver.SetWakeSignal(&wake);
  const Time t = FromUnixNanos(1'000'000'000);
  receiver.Push(Eye::kLeft, Jpeg(t, 40));
  receiver.Push(Eye::kRight, Jpeg(t, 200));
  // A bound far beyond one decode: the wait ends by the receiver's notification.
  ASSERT_TRUE(wake.WaitFor(std::chrono::seconds(30)));
  const std::optional<DecodedStereoPair> pair = receiver.Latest();
  ASSERT_TRUE(pair.has_value());
  EXPECT_LE(pair->received, pair->decode_started);
  EXPECT_LE(pair->decode_started, pair->decoded);
  // Both eyes decoded (one on the helper thread), each with its own picture.
  EXPECT_LT(pair->left.at<cv::Vec3b>(10, 10)[0], 60);
  EXPECT_GT(pair->right.at<cv::Vec3b>(10, 10)[0], 180);
  EXPECT_EQ(wake.notifications(), 1u);
  // A broken pair wakes nobody.
  CompressedImage broken = Jpeg(FromUnixNanos(2'000'000'000), 10);
  broken.data.resize(broken.data.size() / 2);
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(2'000'000'000), 10));
  receiver.Push(Eye::kRight, broken);
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().broken_images == 1; }));
  EXPECT_EQ(wake.notifications(), 1u);
  receiver.SetWakeSignal(nullptr);
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

CompressedImage WithData(Time stamp, std::vector<uint8_t> data) {
  CompressedImage out;
  out.stamp = stamp;
  out.format = "jpeg";
  out.data = std::move(data);
  return out;
}

TEST(StereoReceiverTest, AJpegDeclaringHugeDimensionsIsRefusedBeforeDecoding) {
  StereoReceiver receiver;  // no camera info yet: the 4096 x 4096 limit
  const Time t = FromUnixNanos(1'000'000'000);
  // A few hundred bytes declaring 8000 x 8000 (192 MB once decoded) in each eye.
  const std::vector<uint8_t> bomb =
      testing::WithDeclaredSize(testing::EncodeJpeg(64, 48, 10), 8000, 8000);
  receiver.Push(Eye::kLeft, WithData(t, bomb));
  receiver.Push(Eye::kRight, WithData(t, bomb));
  ReceiverStats stats = receiver.Stats();
  EXPECT_EQ(stats.oversized_images, 2u);
  EXPECT_EQ(stats.broken_images, 0u);
  EXPECT_EQ(stats.images, 2u);
  // Nothing of it was paired or decoded; the next real pair is.
  receiver.Push(Eye::kLeft, Jpeg(t + std::chrono::milliseconds(40), 10));
  receiver.Push(Eye::kRight, Jpeg(t + std::chrono::milliseconds(40), 10));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 1; }));
  EXPECT_EQ(receiver.Latest()->left.cols, 64);
  EXPECT_EQ(receiver.Stats().unpaired_dropped, 0u);
}

TEST(StereoReceiverTest, ImagesLargerThanTheCameraInfoSizeAreRefused) {
  StereoReceiver receiver;
  receiver.SetExpectedSize(Eye::kLeft, 64, 48);
  receiver.SetExpectedSize(Eye::kRight, 64, 48);
  const Time t = FromUnixNanos(1'000'000'000);
  receiver.Push(Eye::kLeft, WithData(t, testing::EncodeJpeg(128, 96, 10)));  // too large
  receiver.Push(Eye::kRight, WithData(t, testing::EncodeJpeg(64, 48, 10)));
  EXPECT_EQ(receiver.Stats().oversized_images, 1u);
  // The robot scaling its images down is fine.
  const Time t2 = t + std::chrono::milliseconds(40);
  receiver.Push(Eye::kLeft, WithData(t2, testing::EncodeJpeg(32, 24, 10)));
  receiver.Push(Eye::kRight, WithData(t2, testing::EncodeJpeg(32, 24, 10)));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 1; }));
  EXPECT_EQ(receiver.Latest()->left.cols, 32);
  EXPECT_EQ(receiver.Stats().oversized_images, 1u);
  // Back to unknown: the fixed limit applies again.
  receiver.SetExpectedSize(Eye::kLeft, 0, 0);
  receiver.SetExpectedSize(Eye::kRight, 0, 0);
  const Time t3 = t2 + std::chrono::milliseconds(40);
  receiver.Push(Eye::kLeft, WithData(t3, testing::EncodeJpeg(128, 96, 10)));
  receiver.Push(Eye::kRight, WithData(t3, testing::EncodeJpeg(128, 96, 10)));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 2; }));
}

TEST(StereoReceiverTest, OneFutureStampedPairDoesNotFreezeTheVideo) {
  FakeClock clock;
  StereoReceiver receiver(&clock);
  timesync::ClockOffsetEstimate offset;  // the robot's clock is this one's, within 5 ms
  offset.known = true;
  offset.uncertainty = std::chrono::milliseconds(5);
  receiver.SetClockOffset(offset);
  const Time future = clock.Now() + std::chrono::hours(24);
  receiver.Push(Eye::kLeft, Jpeg(future, 200));
  receiver.Push(Eye::kRight, Jpeg(future, 200));
  EXPECT_EQ(receiver.Stats().future_dropped, 1u);
  for (int i = 1; i <= 3; ++i) {
    clock.Advance(std::chrono::milliseconds(100));
    const Time stamp = clock.Now() - std::chrono::milliseconds(30);
    receiver.Push(Eye::kLeft, Jpeg(stamp, 10));
    receiver.Push(Eye::kRight, Jpeg(stamp, 10));
    ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == static_cast<uint64_t>(i); }))
        << "pair " << i;
    EXPECT_EQ(receiver.Latest()->stamp, stamp);
  }
  const ReceiverStats stats = receiver.Stats();
  EXPECT_EQ(stats.late_dropped, 0u);
  EXPECT_EQ(stats.future_dropped, 1u);
}

TEST(StereoReceiverTest, AFuturePairBeforeTheOffsetIsKnownFreezesTheVideoOnlyBriefly) {
  FakeClock clock;
  StereoReceiver receiver(&clock);
  receiver.Push(Eye::kLeft, Jpeg(clock.Now() + std::chrono::hours(24), 200));
  receiver.Push(Eye::kRight, Jpeg(clock.Now() + std::chrono::hours(24), 200));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 1; }));
  // Real pairs at 10 Hz look late until the order restarts (2 s and 3 late pairs).
  for (int i = 0; i < 25 && receiver.Stats().pairs_decoded == 1; ++i) {
    clock.Advance(std::chrono::milliseconds(100));
    receiver.Push(Eye::kLeft, Jpeg(clock.Now(), 10));
    receiver.Push(Eye::kRight, Jpeg(clock.Now(), 10));
  }
  ASSERT_TRUE(WaitFor([&] {
    const auto latest = receiver.Latest();
    return latest && latest->stamp == clock.Now();
  }));
  const ReceiverStats stats = receiver.Stats();
  EXPECT_EQ(stats.stamp_resyncs, 1u);
  EXPECT_EQ(stats.late_dropped, 19u);
}

TEST(StereoReceiverTest, APairShownSmallerThanItWasSentIsDecodedAtTheDisplayedSize) {
  StereoReceiver receiver;
  DecodeTarget target;
  target.width_px = 700;  // an eye viewport of 700 x 500: 640 x 480 would not cover it
  target.height_px = 500;
  receiver.SetDecodeTarget(target);
  const Time t = FromUnixNanos(1'000'000'000);
  receiver.Push(Eye::kLeft, WithData(t, testing::EncodeJpeg(1280, 960, 40)));
  receiver.Push(Eye::kRight, WithData(t, testing::EncodeJpeg(1280, 960, 200)));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 1; }));
  DecodedStereoPair pair = *receiver.Latest();
  EXPECT_EQ(pair.scale_denominator, 1);  // 640 x 480 would be smaller than the viewport
  EXPECT_EQ(pair.left.cols, 1280);
  EXPECT_EQ(receiver.Stats().scaled_decodes, 0u);

  target.width_px = 640;
  target.height_px = 480;
  receiver.SetDecodeTarget(target);
  const Time t2 = t + std::chrono::milliseconds(33);
  receiver.Push(Eye::kLeft, WithData(t2, testing::EncodeJpeg(1280, 960, 40)));
  receiver.Push(Eye::kRight, WithData(t2, testing::EncodeJpeg(1280, 960, 200)));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 2; }));
  pair = *receiver.Latest();
  EXPECT_EQ(pair.scale_denominator, 2);
  EXPECT_EQ(pair.source_width_px, 1280);
  EXPECT_EQ(pair.source_height_px, 960);
  EXPECT_EQ(pair.left.cols, 640);
  EXPECT_EQ(pair.left.rows, 480);
  EXPECT_EQ(pair.right.cols, 640);
  EXPECT_EQ(pair.right.rows, 480);
  EXPECT_LT(pair.left.at<cv::Vec3b>(100, 100)[0], 60);
  EXPECT_GT(pair.right.at<cv::Vec3b>(100, 100)[0], 180);
  EXPECT_EQ(receiver.Stats().scaled_decodes, 2u);
}

TEST(StereoReceiverTest, MonoDecodesOnlyTheShownEye) {
  StereoReceiver receiver;
  DecodeTarget left_only;
  left_only.right = false;
  receiver.SetDecodeTarget(left_only);
  for (int i = 1; i <= 3; ++i) {
    const Time t = FromUnixNanos(i * 33'000'000);
    receiver.Push(Eye::kLeft, Jpeg(t, 40));
    receiver.Push(Eye::kRight, Jpeg(t, 200));
    ASSERT_TRUE(
        WaitFor([&] { return receiver.Stats().pairs_decoded == static_cast<uint64_t>(i); }));
  }
  DecodedStereoPair pair = *receiver.Latest();
  EXPECT_EQ(pair.left.cols, 64);
  EXPECT_TRUE(pair.right.empty());
  ReceiverStats stats = receiver.Stats();
  EXPECT_EQ(stats.left_decodes, 3u);
  EXPECT_EQ(stats.right_decodes, 0u);

  DecodeTarget right_only;
  right_only.left = false;
  receiver.SetDecodeTarget(right_only);
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(200'000'000), 40));
  receiver.Push(Eye::kRight, Jpeg(FromUnixNanos(200'000'000), 200));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 4; }));
  pair = *receiver.Latest();
  EXPECT_TRUE(pair.left.empty());
  EXPECT_GT(pair.right.at<cv::Vec3b>(10, 10)[0], 180);
  stats = receiver.Stats();
  EXPECT_EQ(stats.left_decodes, 3u);
  EXPECT_EQ(stats.right_decodes, 1u);

  receiver.SetDecodeTarget(DecodeTarget{});  // a stereo mode: both
  receiver.Push(Eye::kLeft, Jpeg(FromUnixNanos(300'000'000), 40));
  receiver.Push(Eye::kRight, Jpeg(FromUnixNanos(300'000'000), 200));
  ASSERT_TRUE(WaitFor([&] { return receiver.Stats().pairs_decoded == 5; }));
  stats = receiver.Stats();
  EXPECT_EQ(stats.left_decodes, 4u);
  EXPECT_EQ(stats.right_decodes, 2u);
  EXPECT_FALSE(receiver.Latest()->right.empty());
}

}  // namespace
}  // namespace mostar::client
