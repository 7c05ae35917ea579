// StereoReceiver with H.264 frames: join at an IDR, never show a broken picture, ask for IDRs.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <thread>
#include <vector>

#include "common/h264/h264_encoder.h"
#include "common/time/fake_clock.h"
#include "operator_client/video/stereo_receiver.h"

namespace mostar::client {
namespace {

using std::chrono::milliseconds;

template <class Predicate>
bool WaitFor(Predicate predicate) {
  for (int i = 0; i < 2500 && !predicate(); ++i) std::this_thread::sleep_for(milliseconds(2));
  return predicate();
}

// Two encoders in step, as the robot's H264StereoEncoder makes them.
class StereoSource {
 public:
  StereoSource() {
    h264::EncoderSettings settings;
    settings.width_px = 160;
    settings.height_px = 120;
    std::string error;
    left_ = h264::Encoder::Create(settings, &error);
    right_ = h264::Encoder::Create(settings, &error);
    EXPECT_NE(right_, nullptr) << error;
  }
  StereoVideoFrame Next(bool idr = false) {
    if (idr) {
      left_->ForceIdr();
      right_->ForceIdr();
    }
    const uint64_t n = next_++;
    cv::Mat left(120, 160, CV_8UC3, cv::Scalar(static_cast<double>(n * 7 % 200), 60, 90));
    cv::Mat right(120, 160, CV_8UC3, cv::Scalar(200, static_cast<double>(n * 5 % 200), 30));
    cv::rectangle(left, cv::Rect(static_cast<int>(n % 100), 20, 30, 30), cv::Scalar(255, 255, 255),
                  -1);
    h264::EncodedFrame l;
    h264::EncodedFrame r;
    std::string error;
    EXPECT_TRUE(left_->Encode(left, &l, &error)) << error;
    EXPECT_TRUE(right_->Encode(right, &r, &error)) << error;
    StereoVideoFrame frame;
    frame.sequence = n;
    frame.stamp = FromUnixNanos(1'600'000'000'000'000'000 + static_cast<int64_t>(n) * 33'000'000);
    frame.idr = l.idr && r.idr;
    frame.width_px = 160;
    frame.height_px = 120;
    frame.left = std::move(l.data);
    frame.right = std::move(r.data);
    return frame;
  }

 private:
  std::unique_ptr<h264::Encoder> left_;
  std::unique_ptr<h264::Encoder> right_;
  uint64_t next_ = 1;
};

struct Requests {
  std::mutex mutex;
  std::vector<std::pair<uint64_t, std::string>> list;
  size_t size() {
    std::lock_guard<std::mutex> lock(mutex);
    return list.size();
  }
  std::pair<uint64_t, std::string> back() {
    std::lock_guard<std::mutex> lock(mutex);
    return list.back();
  }
};

class StereoReceiverH264Test : public ::testing::Test {
 protected:
  StereoReceiverH264Test() : receiver_(&clock_) {
    receiver_.SetKeyframeRequester([this](uint64_t last, const std::string& reason) {
      std::lock_guard<std::mutex> lock(requests_.mutex);
      requests_.list.emplace_back(last, reason);
    });
  }
  // Pushes `frame` and waits until the receiver has dealt with it.
  void Push(const StereoVideoFrame& frame) {
    const uint64_t done = receiver_.Stats().pairs_decoded + receiver_.Stats().video_skipped;
    receiver_.PushVideo(frame);
    ASSERT_TRUE(WaitFor([&] {
      const ReceiverStats stats = receiver_.Stats();
      return stats.pairs_decoded + stats.video_skipped > done;
    }));
  }

  FakeClock clock_;
  Requests requests_;
  StereoReceiver receiver_;
  StereoSource source_;
};

TEST_F(StereoReceiverH264Test, DecodesBothEyesOfEveryFrame) {
  for (int i = 0; i < 5; ++i) Push(source_.Next());
  const std::optional<DecodedStereoPair> pair = receiver_.Latest();
  ASSERT_TRUE(pair.has_value());
  EXPECT_EQ(pair->stamp, FromUnixNanos(1'600'000'000'000'000'000 + 5 * 33'000'000));
  EXPECT_EQ(pair->left.cols, 160);
  EXPECT_EQ(pair->right.rows, 120);
  EXPECT_EQ(pair->left.type(), CV_8UC3);
  EXPECT_GT(pair->right.at<cv::Vec3b>(60, 150)[0], 150);  // the right eye's blue
  const ReceiverStats stats = receiver_.Stats();
  EXPECT_EQ(stats.pairs_decoded, 5u);
  EXPECT_EQ(stats.video_frames, 5u);
  EXPECT_FALSE(stats.waiting_for_keyframe);
  EXPECT_EQ(requests_.size(), 0u);
}

TEST_F(StereoReceiverH264Test, JoiningMidStreamShowsNothingUntilAnIdrAndAsksForOne) {
  source_.Next();  // the IDR this viewer missed
  Push(source_.Next());
  EXPECT_FALSE(receiver_.Latest().has_value());
  EXPECT_TRUE(receiver_.Stats().waiting_for_keyframe);
  ASSERT_EQ(requests_.size(), 1u);
  EXPECT_EQ(requests_.back().second, "join");
  Push(source_.Next());  // within 200 ms: not asked again
  EXPECT_EQ(requests_.size(), 1u);
  clock_.Advance(milliseconds(200));
  Push(source_.Next());  // still no IDR 200 ms later: asked again
  EXPECT_EQ(requests_.size(), 2u);
  Push(source_.Next(/*idr=*/true));
  ASSERT_TRUE(receiver_.Latest().has_value());
  EXPECT_FALSE(receiver_.Stats().waiting_for_keyframe);
  EXPECT_EQ(receiver_.Stats().video_skipped, 3u);
}

TEST_F(StereoReceiverH264Test, ALostFrameFreezesTheLastGoodPairUntilTheNextIdr) {
  for (int i = 0; i < 4; ++i) Push(source_.Next());
  const Time last_good = receiver_.Latest()->stamp;
  source_.Next();  // lost on the way
  for (int i = 0; i < 3; ++i) Push(source_.Next());
  EXPECT_EQ(receiver_.Latest()->stamp, last_good);  // stale, never a broken picture
  EXPECT_TRUE(receiver_.Stats().waiting_for_keyframe);
  EXPECT_EQ(receiver_.Stats().video_gaps, 1u);
  ASSERT_EQ(requests_.size(), 1u);
  EXPECT_EQ(requests_.back().first, 4u);  // the last AU decoded
  EXPECT_EQ(requests_.back().second, "gap");
  const StereoVideoFrame idr = source_.Next(/*idr=*/true);
  Push(idr);
  EXPECT_EQ(receiver_.Latest()->stamp, idr.stamp);
  EXPECT_FALSE(receiver_.Stats().waiting_for_keyframe);
  Push(source_.Next());
  EXPECT_EQ(receiver_.Stats().pairs_decoded, 6u);
}

TEST_F(StereoReceiverH264Test, ADamagedFrameIsNotShownAndAsksForAnIdr) {
  for (int i = 0; i < 3; ++i) Push(source_.Next());
  StereoVideoFrame damaged = source_.Next();
  std::fill(damaged.right.begin() + 5, damaged.right.end(), 0xff);
  Push(damaged);
  Push(source_.Next());
  EXPECT_EQ(receiver_.Stats().pairs_decoded, 3u);
  EXPECT_TRUE(receiver_.Stats().waiting_for_keyframe);
  ASSERT_GE(requests_.size(), 1u);
  Push(source_.Next(/*idr=*/true));
  EXPECT_EQ(receiver_.Stats().pairs_decoded, 4u);
}

TEST_F(StereoReceiverH264Test, ArrivalsAreReportedForTheRobotsRateControl) {
  std::mutex mutex;
  std::vector<VideoFrameArrival> reported;
  int reports = 0;
  receiver_.SetFeedbackSender([&](const std::vector<VideoFrameArrival>& arrivals) {
    std::lock_guard<std::mutex> lock(mutex);
    reported.insert(reported.end(), arrivals.begin(), arrivals.end());
    ++reports;
  });
  Push(source_.Next());  // the first is reported at once
  for (int i = 0; i < 3; ++i) {
    clock_.Advance(milliseconds(20));
    Push(source_.Next());
  }
  clock_.Advance(milliseconds(50));
  Push(source_.Next());
  std::lock_guard<std::mutex> lock(mutex);
  EXPECT_EQ(reports, 3);  // 0 ms, 60 ms (>= 50 ms), 110 ms
  ASSERT_EQ(reported.size(), 5u);
  for (size_t i = 0; i < reported.size(); ++i) EXPECT_EQ(reported[i].sequence, i + 1);
  EXPECT_EQ(reported[1].arrival_ns - reported[0].arrival_ns, 20'000'000);
  EXPECT_GT(reported[0].bytes, 0u);
  receiver_.SetFeedbackSender(nullptr);
}

TEST_F(StereoReceiverH264Test, AnotherFormatIsRefused) {
  StereoVideoFrame frame = source_.Next(true);
  frame.format = "vp9";
  receiver_.PushVideo(frame);
  EXPECT_EQ(receiver_.Stats().broken_images, 1u);
  EXPECT_EQ(receiver_.Stats().pairs_decoded, 0u);
}

}  // namespace
}  // namespace mostar::client
