#include "robot_server/camera/camera_pipeline.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <thread>

#include "common/h264/h264_decoder.h"
#include "common/jpeg/jpeg_decoder.h"
#include "common/time/fake_clock.h"
#include "robot_server/camera/fake_stereo_camera.h"
#include "robot_server/camera/jpeg_compressor.h"

namespace mostar::camera {
namespace {

using std::chrono::milliseconds;

// Waits (polling) until `predicate` holds; false after 20 s. Threads are real here, so the
// test waits for an observable state instead of sleeping a fixed time.
template <typename Predicate>
bool WaitFor(Predicate predicate) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!predicate()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(milliseconds(1));
  }
  return true;
}

uint64_t Counter(const DeviceHealth& health, const std::string& name) {
  for (const auto& [key, value] : health.counters) {
    if (key == name) return value;
  }
  ADD_FAILURE() << "no counter " << name;
  return 0;
}

// Quick reopening; grab timeouts long enough not to disturb the state checks.
CameraPipelineOptions FastOptions() {
  CameraPipelineOptions options;
  options.name = "test_camera";
  options.grab_timeout = milliseconds(300);
  options.max_consecutive_timeouts = 1000;
  options.reopen_period = milliseconds(1);
  return options;
}

// Every Grab() of an empty script times out after 20 ms; three in a row reopen the camera.
CameraPipelineOptions TimeoutOptions() {
  CameraPipelineOptions options = FastOptions();
  options.grab_timeout = milliseconds(20);
  options.max_consecutive_timeouts = 3;
  return options;
}

class CameraPipelineTest : public ::testing::Test {
 protected:
  CameraPipelineTest() {
    FakeStereoCamera::Options options;
    options.width_px = 160;
    options.height_px = 120;
    auto camera = std::make_unique<FakeStereoCamera>(options);
    camera_ = camera.get();
    camera_owned_ = std::move(camera);
  }

  void StartPipeline(const CameraPipelineOptions& options) {
    pipeline_ = std::make_unique<CameraPipeline>(
        std::move(camera_owned_), options, [this](const CompressedStereoPair& pair) {
          std::string error;
          cv::Mat left;
          if (!decoder_.Decode(pair.left.data, &left, &error)) ++bad_;
          last_sequence_ = pair.sequence;
          if (pair.encoded < pair.left.stamp) ++encoded_before_capture_;
          ++delivered_;
          return skip_all_ ? Delivery::kSkipped : Delivery::kSent;
        });
    pipeline_->Start();
  }

  FakeStereoCamera* camera_;
  std::unique_ptr<FakeStereoCamera> camera_owned_;
  std::unique_ptr<CameraPipeline> pipeline_;
  JpegDecoder decoder_;  // used on the compression thread only
  std::atomic<int> delivered_{0};
  std::atomic<int> bad_{0};
  std::atomic<int> encoded_before_capture_{0};  // pairs whose encode stamp precedes capture
  std::atomic<uint64_t> last_sequence_{0};
  std::atomic<bool> skip_all_{false};
};

TEST_F(CameraPipelineTest, DeliversCompressedPairsAndReportsHealth) {
  StartPipeline(FastOptions());
  camera_->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return delivered_ >= 1; }));
  camera_->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return delivered_ >= 2; }));
  EXPECT_EQ(bad_, 0);
  EXPECT_EQ(encoded_before_capture_, 0);
  const DeviceHealth health = pipeline_->Health();
  EXPECT_EQ(health.name, "test_camera");
  EXPECT_NE(health.state, DeviceState::kError) << health.message;
  EXPECT_EQ(Counter(health, "frames"), 2u);
  EXPECT_EQ(Counter(health, "pairs_delivered"), 2u);
  EXPECT_EQ(Counter(health, "encode_errors"), 0u);
  EXPECT_EQ(Counter(health, "jpeg_quality"), 80u);
  EXPECT_EQ(Counter(health, "jpeg_scale_percent"), 100u);
  EXPECT_EQ(Counter(health, "fake_pairs_delivered"), 2u);  // the camera's own counters
  pipeline_->Stop();
  EXPECT_EQ(pipeline_->Health().state, DeviceState::kOff);
}

TEST_F(CameraPipelineTest, ReopensTheCameraAfterItIsUnpluggedAndReturns) {
  StartPipeline(FastOptions());
  camera_->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return delivered_ >= 1; }));

  camera_->Unplug();
  ASSERT_TRUE(WaitFor([&] { return Counter(pipeline_->Health(), "reopen_attempts") >= 3; }));
  DeviceHealth health = pipeline_->Health();
  EXPECT_EQ(health.state, DeviceState::kError);
  EXPECT_NE(health.message.find("unplugged"), std::string::npos) << health.message;
  EXPECT_GE(Counter(health, "device_lost"), 1u);
  EXPECT_GE(Counter(health, "open_failures"), 3u);

  camera_->Replug();
  ASSERT_TRUE(WaitFor([&] { return pipeline_->Health().state == DeviceState::kOk; }));
  camera_->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return delivered_ >= 2; }));
  EXPECT_EQ(Counter(pipeline_->Health(), "pairs_delivered"), 2u);
}

TEST_F(CameraPipelineTest, RepeatedTimeoutsCloseAndReopenTheCamera) {
  StartPipeline(TimeoutOptions());
  ASSERT_TRUE(WaitFor([&] { return camera_->close_calls() >= 1 && camera_->open_calls() >= 2; }));
  const DeviceHealth health = pipeline_->Health();
  EXPECT_GE(Counter(health, "timeouts"), 3u);
  EXPECT_GE(Counter(health, "reopen_attempts"), 1u);
  camera_->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return delivered_ >= 1; }));
}

TEST_F(CameraPipelineTest, AScriptedLossIsReportedAndRecovered) {
  camera_->SetOpenFailures(0);
  StartPipeline(FastOptions());
  camera_->QueueDeviceLost();
  camera_->SetOpenFailures(2);
  ASSERT_TRUE(WaitFor([&] { return Counter(pipeline_->Health(), "device_lost") >= 1; }));
  camera_->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return delivered_ >= 1; }));
  EXPECT_GE(Counter(pipeline_->Health(), "open_failures"), 2u);
}

TEST_F(CameraPipelineTest, SkippedPairsAreCountedAndLowerTheQuality) {
  skip_all_ = true;
  CameraPipelineOptions options = FastOptions();
  options.bitrate.control_interval_pairs = 1;
  StartPipeline(options);
  for (int i = 1; i <= 30; ++i) {
    camera_->QueuePairs(1);
    ASSERT_TRUE(WaitFor([&] { return delivered_ >= i; }));
  }
  const DeviceHealth health = pipeline_->Health();
  EXPECT_EQ(Counter(health, "pairs_skipped_at_source"), 30u);
  EXPECT_EQ(Counter(health, "pairs_delivered"), 0u);
  EXPECT_LT(Counter(health, "jpeg_quality"), 80u);
}

TEST_F(CameraPipelineTest, StopsCleanlyWhileTheCameraIsAbsent) {
  camera_->Unplug();
  StartPipeline(FastOptions());
  ASSERT_TRUE(WaitFor([&] { return Counter(pipeline_->Health(), "open_failures") >= 2; }));
  pipeline_->Stop();
  pipeline_->Stop();  // idempotent
  EXPECT_EQ(pipeline_->Health().state, DeviceState::kOff);
  EXPECT_EQ(delivered_, 0);
}

TEST_F(CameraPipelineTest, BitrateClassesSwitchTheTarget) {
  StartPipeline(FastOptions());
  EXPECT_FALSE(pipeline_->SetBitrateClass("satellite"));
  EXPECT_TRUE(pipeline_->SetBitrateClass("wan"));
  camera_->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return delivered_ >= 1; }));
  EXPECT_EQ(pipeline_->bitrate_stats().target_bits_per_s, 8e6);
  EXPECT_EQ(Counter(pipeline_->Health(), "target_bitrate_bps"), 8'000'000u);
}

// Codec H264: every pair becomes a StereoVideoFrame with consecutive AU numbers, starting with
// an IDR; a keyframe request makes the next pair an IDR, at most one per 300 ms.
TEST(CameraPipelineH264Test, DeliversNumberedFramesAndAnswersKeyframeRequests) {
  FakeClock clock;  // the keyframe interval is judged on it
  FakeStereoCamera::Options camera_options;
  camera_options.width_px = 160;
  camera_options.height_px = 120;
  camera_options.clock = &clock;
  auto owned_camera = std::make_unique<FakeStereoCamera>(camera_options);
  FakeStereoCamera* camera = owned_camera.get();
  CameraPipelineOptions options = FastOptions();
  options.codec = VideoCodec::kH264;
  options.h264.keyint_frames = 1000;
  std::mutex mutex;
  std::vector<StereoVideoFrame> frames;
  std::string error;
  std::unique_ptr<h264::Decoder> left = h264::Decoder::Create(&error);
  ASSERT_NE(left, nullptr) << error;
  int pictures = 0;
  CameraPipeline pipeline(
      std::move(owned_camera), options, [](const CompressedStereoPair&) { return Delivery::kSent; },
      &clock);
  pipeline.SetVideoDelivery([&](const StereoVideoFrame& frame) {
    std::lock_guard<std::mutex> lock(mutex);
    cv::Mat image;
    std::string why;
    if (left->Decode(frame.left.data(), frame.left.size(), frame.sequence, &image, &why) ==
        h264::DecodeStatus::kPicture) {
      ++pictures;
    }
    frames.push_back(frame);
    return Delivery::kSent;
  });
  const auto count = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return frames.size();
  };
  pipeline.Start();
  for (int i = 0; i < 3; ++i) {
    camera->QueuePairs(1);
    ASSERT_TRUE(WaitFor([&] { return count() >= static_cast<size_t>(i + 1); }));
    clock.Advance(milliseconds(33));
  }
  clock.Advance(milliseconds(300));  // past the interval of the first IDR
  pipeline.RequestKeyframe();
  camera->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return count() >= 4; }));
  clock.Advance(milliseconds(33));
  camera->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return count() >= 5; }));
  clock.Advance(milliseconds(33));
  pipeline.RequestKeyframe();  // 66 ms after the last IDR: deferred to its 300 ms
  camera->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return count() >= 6; }));
  clock.Advance(milliseconds(234));
  camera->QueuePairs(1);
  ASSERT_TRUE(WaitFor([&] { return count() >= 7; }));
  // The counters follow the delivery callback.
  ASSERT_TRUE(WaitFor([&] { return Counter(pipeline.Health(), "pairs_delivered") == 7; }));
  std::lock_guard<std::mutex> lock(mutex);
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].sequence, i + 1);
    EXPECT_EQ(frames[i].format, "h264");
    EXPECT_EQ(frames[i].width_px, 160);
    EXPECT_EQ(frames[i].height_px, 120);
    EXPECT_FALSE(frames[i].left.empty());
    EXPECT_FALSE(frames[i].right.empty());
    EXPECT_FALSE(frames[i].encoded < frames[i].stamp);
  }
  EXPECT_TRUE(frames[0].idr);
  EXPECT_FALSE(frames[1].idr);
  EXPECT_FALSE(frames[2].idr);
  EXPECT_TRUE(frames[3].idr);  // answered
  EXPECT_FALSE(frames[4].idr);
  EXPECT_FALSE(frames[5].idr);  // the second request waits for the end of the interval
  EXPECT_TRUE(frames[6].idr);   // 300 ms after the last IDR
  EXPECT_EQ(pictures, 7);
  const DeviceHealth health = pipeline.Health();
  EXPECT_EQ(Counter(health, "h264_idrs"), 3u);
  EXPECT_EQ(Counter(health, "keyframe_requests"), 2u);
  EXPECT_EQ(Counter(health, "keyframe_requests_deferred"), 1u);
  EXPECT_EQ(Counter(health, "pairs_delivered"), 7u);
}

TEST(CameraPipelineOptionsTest, ValidationNamesTheProblem) {
  std::string error;
  CameraPipelineOptions options;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  options.bitrate_classes["bad"] = -1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("bad"), std::string::npos);
}

// With a slow consumer the slot drops the older pairs instead of queueing them.
TEST(CameraPipelineSlotTest, ASlowConsumerDropsPairsAtTheSource) {
  FakeStereoCamera::Options camera_options;
  camera_options.width_px = 160;
  camera_options.height_px = 120;
  camera_options.free_run = true;  // as fast as the capture thread can go
  std::atomic<int> delivered{0};
  CameraPipeline pipeline(std::make_unique<FakeStereoCamera>(camera_options), FastOptions(),
                          [&](const CompressedStereoPair&) {
                            std::this_thread::sleep_for(milliseconds(20));
                            ++delivered;
                            return Delivery::kSent;
                          });
  pipeline.Start();
  ASSERT_TRUE(WaitFor([&] { return delivered >= 5; }));
  pipeline.Stop();
  const DeviceHealth health = pipeline.Health();
  EXPECT_GT(Counter(health, "slot_drops"), 0u);
  EXPECT_GT(Counter(health, "frames"), Counter(health, "pairs_delivered"));
}

}  // namespace
}  // namespace mostar::camera
