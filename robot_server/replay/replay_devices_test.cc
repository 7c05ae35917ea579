// The replay backends on a small recording written with the real writer: order, stamps, pacing
// on a FakeClock (the injected sleep advances it, so due times are met exactly), rate, looping,
// end of recording, broken JPEGs, overdue pairs, reopening, damage.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <thread>
#include <vector>

#include "common/record/recording_writer.h"
#include "common/record/test_records.h"
#include "common/time/fake_clock.h"
#include "robot_server/camera/camera_factory.h"
#include "robot_server/replay/replay_laser_scanner.h"
#include "robot_server/replay/replay_stereo_camera.h"
#include "robot_server/replay/replay_timeline.h"

namespace mostar::replay {
namespace {

using record::testing::T0;
using std::chrono::milliseconds;

constexpr int kPairs = 10;
constexpr int kScans = 25;
constexpr int kBrokenPair = 3;  // its left eye is not a JPEG
const Duration kFramePeriod = milliseconds(100);
const Duration kScanPeriod = milliseconds(40);

// Grey level of pair k: the images tell which pair was delivered.
int GreyOf(int k) { return 20 + 20 * k; }

CompressedImage Jpeg(int grey, Time stamp, Eye eye) {
  CompressedImage image;
  image.stamp = stamp;
  image.frame_id = eye == Eye::kLeft ? "camera_left" : "camera_right";
  image.format = "jpeg";
  const cv::Mat pixels(24, 32, CV_8UC3, cv::Scalar(grey, grey, grey));
  EXPECT_TRUE(cv::imencode(".jpg", pixels, image.data));
  return image;
}

Time PairStamp(int k) { return T0() + k * kFramePeriod; }
Time PairLogTime(int k) { return PairStamp(k) + milliseconds(6); }  // the later eye
Time ScanStamp(int k) { return T0() + k * kScanPeriod; }
Time ScanLogTime(int k) { return ScanStamp(k) + milliseconds(2); }

// Pairs every 100 ms (eyes logged 5 and 6 ms after capture), scans every 40 ms (logged 2 ms
// after), odometry in between, in log-time order. Returns the file's last log time.
Time WriteRecording(const std::string& path) {
  std::vector<record::RecordedMessage> messages;
  for (int k = 0; k < kPairs; ++k) {
    record::RecordedImage left;
    left.eye = Eye::kLeft;
    left.pair_sequence = static_cast<uint64_t>(k + 1);
    left.image = Jpeg(GreyOf(k), PairStamp(k), Eye::kLeft);
    if (k == kBrokenPair) left.image.data.assign(300, 0x5A);
    record::RecordedImage right = left;
    right.eye = Eye::kRight;
    right.image = Jpeg(GreyOf(k), PairStamp(k), Eye::kRight);
    messages.push_back(record::testing::At(PairStamp(k) + milliseconds(5), left));
    messages.push_back(record::testing::At(PairLogTime(k), right));
  }
  for (int k = 0; k < kScans; ++k) {
    messages.push_back(
        record::testing::At(ScanLogTime(k), record::testing::MakeScan(ScanStamp(k), 100 + k)));
    messages.push_back(record::testing::At(ScanLogTime(k) + milliseconds(1),
                                           record::testing::MakeOdometry(ScanStamp(k))));
  }
  std::stable_sort(messages.begin(), messages.end(),
                   [](const auto& a, const auto& b) { return a.log_time < b.log_time; });
  FakeClock clock(T0());
  std::string error;
  auto writer = record::RecordingWriter::Open(path, {}, record::testing::MakeInfo(), clock, &error);
  EXPECT_NE(writer, nullptr) << error;
  for (const auto& m : messages) EXPECT_TRUE(writer->Write(m));
  EXPECT_TRUE(writer->Close(&error)) << error;
  return messages.back().log_time;
}

class ReplayDevicesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = record::testing::TempPath("replay_devices.mostar");
    last_log_time_ = WriteRecording(path_);
  }
  void TearDown() override { std::remove(path_.c_str()); }

  std::shared_ptr<ReplayTimeline> Timeline(ReplayTimelineOptions options = {}) {
    std::string error;
    auto timeline = ReplayTimeline::ForRecording(path_, clock_, options, &error);
    EXPECT_NE(timeline, nullptr) << error;
    return timeline;
  }
  // On the fake clock: waiting advances it.
  ReplayStereoCamera::Options CameraOptions(std::shared_ptr<ReplayTimeline> timeline) {
    ReplayDeviceOptions options;
    options.path = path_;
    options.timeline = std::move(timeline);
    options.clock = &clock_;
    options.sleep = [this](Duration d) { clock_.Advance(d); };
    return options;
  }
  ReplayLaserScanner::Options LaserOptions(std::shared_ptr<ReplayTimeline> timeline) {
    ReplayLaserScanner::Options options;
    static_cast<ReplayDeviceOptions&>(options) = CameraOptions(std::move(timeline));
    return options;
  }
  static int Grey(const cv::Mat& image) {
    return static_cast<int>(std::lround(cv::mean(image)[0]));
  }

  std::string path_;
  Time last_log_time_;
  FakeClock clock_{FromUnixNanos(1'800'000'000'000'000'000)};  // the replay's "now"
};

TEST_F(ReplayDevicesTest, TimelineSpansTheRecordingAndMapsTimes) {
  ReplayTimelineOptions options;
  options.rate = 2.0;
  options.loop = true;
  options.loop_gap = milliseconds(100);
  auto timeline = Timeline(options);
  ASSERT_NE(timeline, nullptr);
  EXPECT_EQ(timeline->begin(), ScanLogTime(0));  // the first record is scan 0
  EXPECT_EQ(timeline->end(), last_log_time_);
  EXPECT_EQ(timeline->loop_period(), last_log_time_ - ScanLogTime(0) + milliseconds(100));
  const SteadyTime s0 = clock_.SteadyNow();
  const Time w0 = clock_.Now();
  timeline->Start();
  clock_.Advance(milliseconds(7));
  timeline->Start();  // only the first call anchors
  const Time r = ScanLogTime(0) + milliseconds(300);
  EXPECT_EQ(timeline->DueTime(r, 0), s0 + milliseconds(150));
  EXPECT_EQ(timeline->DueTime(r, 1), s0 + milliseconds(150) + timeline->loop_period() / 2);
  EXPECT_EQ(timeline->Restamp(r, 1), w0 + (milliseconds(300) + timeline->loop_period()) / 2);
  uint64_t pass = 9;
  EXPECT_EQ(timeline->RecordingNow(&pass), ScanLogTime(0) + milliseconds(14));
  EXPECT_EQ(pass, 0u);
  clock_.Advance(timeline->loop_period() / 2);  // one period later, at rate 2
  EXPECT_EQ(timeline->RecordingNow(&pass), ScanLogTime(0) + milliseconds(14));
  EXPECT_EQ(pass, 1u);

  std::string error;
  EXPECT_EQ(ReplayTimeline::ForRecording(path_ + ".missing", clock_, {}, &error), nullptr);
  EXPECT_NE(error.find(".missing"), std::string::npos) << error;
  options.rate = 0;
  EXPECT_EQ(ReplayTimeline::ForRecording(path_, clock_, options, &error), nullptr);
}

TEST_F(ReplayDevicesTest, CameraDeliversPairsInOrderAtTheirLogTimes) {
  auto timeline = Timeline();
  ReplayStereoCamera camera(CameraOptions(timeline));
  const SteadyTime s0 = clock_.SteadyNow();
  const Time w0 = clock_.Now();
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  const camera::StereoCameraInfo info = camera.Info();
  EXPECT_EQ(info.backend, "replay");
  EXPECT_EQ(info.width_px, 32);
  EXPECT_EQ(info.height_px, 24);
  EXPECT_FLOAT_EQ(static_cast<float>(info.frame_rate_hz), 15.f);  // recorded, times rate 1

  const Time begin = timeline->begin();
  uint64_t last_sequence = 0;
  for (int k = 0; k < kPairs; ++k) {
    if (k == kBrokenPair) continue;
    camera::StereoImagePair pair;
    const camera::GrabResult result = camera.Grab(std::chrono::seconds(1), &pair);
    ASSERT_TRUE(result.ok()) << k << ": " << result.message;
    EXPECT_EQ(Grey(pair.left), GreyOf(k)) << "pair " << k;
    EXPECT_NEAR(Grey(pair.right), GreyOf(k), 1);
    EXPECT_EQ(pair.left.type(), CV_8UC3);
    // Due exactly at its log time on the replay's clock, stamped on the replay's wall clock.
    EXPECT_EQ(clock_.SteadyNow(), s0 + (PairLogTime(k) - begin)) << "pair " << k;
    EXPECT_EQ(pair.stamp, w0 + (PairStamp(k) - begin)) << "pair " << k;
    // The skipped broken pair leaves a gap in the sequence.
    EXPECT_EQ(pair.sequence, last_sequence + (k == kBrokenPair + 1 ? 2 : 1));
    last_sequence = pair.sequence;
  }
  EXPECT_EQ(camera.broken_jpegs(), 1u);
  EXPECT_EQ(camera.pairs_replayed(), static_cast<uint64_t>(kPairs - 1));
  camera::StereoImagePair pair;
  const camera::GrabResult end = camera.Grab(std::chrono::seconds(1), &pair);
  EXPECT_EQ(end.status, camera::GrabStatus::kEndOfStream);
  EXPECT_NE(end.message.find("end of recording"), std::string::npos) << end.message;
  EXPECT_NE(end.message.find("9 pairs"), std::string::npos) << end.message;
  bool broken_counter = false;
  for (const auto& [name, value] : camera.Counters()) {
    if (name == "broken_jpegs") broken_counter = value == 1;
  }
  EXPECT_TRUE(broken_counter);
}

TEST_F(ReplayDevicesTest, CameraDeliversPairsAtTheirCaptureStampsWhenAsked) {
  auto timeline = Timeline();
  ReplayStereoCamera::Options options = CameraOptions(timeline);
  options.due_at_stamp = true;
  ReplayStereoCamera camera(options);
  const SteadyTime s0 = clock_.SteadyNow();
  const Time w0 = clock_.Now();
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  const Time begin = timeline->begin();
  for (int k = 0; k < kPairs; ++k) {
    if (k == kBrokenPair) continue;
    camera::StereoImagePair pair;
    ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok()) << k;
    EXPECT_EQ(Grey(pair.left), GreyOf(k)) << "pair " << k;
    // Due at its capture stamp, 6 ms before its log time (pair 0's stamp precedes the
    // recording's first log time: delivered at once).
    EXPECT_EQ(clock_.SteadyNow(), std::max(s0, s0 + (PairStamp(k) - begin))) << "pair " << k;
    EXPECT_EQ(pair.stamp, w0 + (PairStamp(k) - begin)) << "pair " << k;
  }
}

TEST_F(ReplayDevicesTest, CameraRateScalesThePacing) {
  ReplayTimelineOptions options;
  options.rate = 4.0;
  ReplayStereoCamera camera(CameraOptions(Timeline(options)));
  const SteadyTime s0 = clock_.SteadyNow();
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  camera::StereoImagePair pair;
  ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok());
  ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok());
  EXPECT_EQ(Grey(pair.left), GreyOf(1));
  EXPECT_EQ(clock_.SteadyNow(), s0 + (PairLogTime(1) - ScanLogTime(0)) / 4);
}

TEST_F(ReplayDevicesTest, CameraTimesOutBeforeAPairIsDue) {
  ReplayStereoCamera camera(CameraOptions(Timeline()));
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  camera::StereoImagePair pair;
  ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok());  // pair 0
  const SteadyTime before = clock_.SteadyNow();
  const camera::GrabResult result = camera.Grab(milliseconds(30), &pair);
  EXPECT_EQ(result.status, camera::GrabStatus::kTimeout);
  EXPECT_EQ(clock_.SteadyNow(), before + milliseconds(30));  // waited the whole timeout
  ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok());
  EXPECT_EQ(Grey(pair.left), GreyOf(1));
}

TEST_F(ReplayDevicesTest, CameraLoopsWithIncreasingStamps) {
  ReplayTimelineOptions options;
  options.loop = true;
  auto timeline = Timeline(options);
  ReplayStereoCamera camera(CameraOptions(timeline));
  const SteadyTime s0 = clock_.SteadyNow();
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  std::vector<int> greys;
  Time last_stamp = Time::min();
  for (int i = 0; i < 2 * (kPairs - 1) + 1; ++i) {
    camera::StereoImagePair pair;
    const camera::GrabResult result = camera.Grab(std::chrono::seconds(1), &pair);
    ASSERT_TRUE(result.ok()) << result.message;
    EXPECT_GT(pair.stamp, last_stamp);
    last_stamp = pair.stamp;
    greys.push_back(Grey(pair.left));
  }
  EXPECT_EQ(greys[kPairs - 1], GreyOf(0)) << "the second pass starts with pair 0";
  EXPECT_EQ(greys[2 * (kPairs - 1)], GreyOf(0)) << "and the third";
  EXPECT_EQ(camera.pass(), 2u);
  EXPECT_EQ(camera.broken_jpegs(), 2u);  // once per completed pass
  // The third pass's pair 0 is due two loop periods after the first's.
  EXPECT_EQ(clock_.SteadyNow(),
            s0 + (PairLogTime(0) - timeline->begin()) + 2 * timeline->loop_period());
}

TEST_F(ReplayDevicesTest, CameraDecodesOnlyTheNewestOverduePair) {
  ReplayStereoCamera camera(CameraOptions(Timeline()));
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  // The capture thread comes back late: pairs 0..4 are due, the broken pair 3 among them.
  clock_.Advance(PairLogTime(4) - ScanLogTime(0) + milliseconds(10));
  camera::StereoImagePair pair;
  ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok());
  EXPECT_EQ(Grey(pair.left), GreyOf(4));
  EXPECT_EQ(pair.sequence, 5u);  // 4 skipped pairs show as a gap
  EXPECT_EQ(camera.pairs_skipped_late(), 4u);
  EXPECT_EQ(camera.broken_jpegs(), 0u) << "the broken pair was skipped without decoding";
}

TEST_F(ReplayDevicesTest, CameraReopenResumesAtTheTimelinePosition) {
  auto timeline = Timeline();
  ReplayStereoCamera camera(CameraOptions(timeline));
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  camera::StereoImagePair pair;
  ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok());
  camera.Close();
  EXPECT_FALSE(camera.IsOpen());
  EXPECT_EQ(camera.Grab(milliseconds(10), &pair).status, camera::GrabStatus::kNotOpen);
  clock_.Advance(milliseconds(550));  // now between pairs 5 and 6
  ASSERT_TRUE(camera.Open(&error)) << error;
  ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok());
  EXPECT_EQ(Grey(pair.left), GreyOf(6));
}

TEST_F(ReplayDevicesTest, CameraReportsDamageAndMissingFiles) {
  const std::string bytes = record::testing::ReadFileBytes(path_);
  const std::string cut = path_ + ".cut";
  record::testing::WriteFileBytes(cut, bytes.substr(0, bytes.size() / 2));
  ReplayStereoCamera::Options options = CameraOptions(Timeline());
  options.path = cut;
  ReplayStereoCamera camera(options);
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  camera::GrabResult result;
  int pairs = 0;
  for (int i = 0; i < 2 * kPairs; ++i) {
    camera::StereoImagePair pair;
    result = camera.Grab(std::chrono::seconds(1), &pair);
    if (!result.ok()) break;
    ++pairs;
  }
  EXPECT_EQ(result.status, camera::GrabStatus::kEndOfStream);
  EXPECT_NE(result.message.find("damaged at byte"), std::string::npos) << result.message;
  EXPECT_GT(pairs, 0);
  EXPECT_LT(pairs, kPairs - 1);
  std::remove(cut.c_str());

  options.path = path_ + ".missing";
  ReplayStereoCamera missing(options);
  EXPECT_FALSE(missing.Open(&error));
  EXPECT_NE(error.find(".missing"), std::string::npos) << error;
}

struct Received {
  LaserScan scan;
  SteadyTime at;
};

TEST_F(ReplayDevicesTest, LaserDeliversEveryScanAtItsLogTimeThenEnds) {
  auto timeline = Timeline();
  ReplayLaserScanner laser(LaserOptions(timeline));
  const SteadyTime s0 = clock_.SteadyNow();
  const Time w0 = clock_.Now();
  std::mutex mutex;
  std::vector<Received> received;
  std::string error;
  ASSERT_TRUE(laser.Start(
      [&](const LaserScan& scan) {
        std::lock_guard<std::mutex> lock(mutex);
        received.push_back({scan, clock_.SteadyNow()});
      },
      &error))
      << error;
  for (int i = 0; i < 500 && !laser.finished(); ++i) std::this_thread::sleep_for(milliseconds(10));
  ASSERT_TRUE(laser.finished());
  std::string again;
  EXPECT_FALSE(laser.Start([](const LaserScan&) {}, &again)) << "started twice";
  laser.Stop();
  ASSERT_EQ(received.size(), static_cast<size_t>(kScans));
  for (int k = 0; k < kScans; ++k) {
    EXPECT_EQ(received[k].at, s0 + (ScanLogTime(k) - timeline->begin())) << "scan " << k;
    EXPECT_EQ(received[k].scan.stamp, w0 + (ScanStamp(k) - timeline->begin())) << "scan " << k;
    EXPECT_EQ(received[k].scan.sequence, static_cast<uint64_t>(k + 1));
    EXPECT_EQ(received[k].scan.ranges_m.size(), 181u);
  }
  const DeviceHealth health = laser.Health();
  EXPECT_EQ(health.name, "laser_replay");
  EXPECT_EQ(health.state, DeviceState::kOff);
  EXPECT_NE(health.message.find("end of recording"), std::string::npos) << health.message;
  EXPECT_NE(health.message.find("25 scans"), std::string::npos) << health.message;
}

TEST_F(ReplayDevicesTest, LaserLoopsAndStops) {
  ReplayTimelineOptions options;
  options.loop = true;
  auto timeline = Timeline(options);
  ReplayLaserScanner laser(LaserOptions(timeline));
  std::mutex mutex;
  std::vector<Received> received;
  std::string error;
  ASSERT_TRUE(laser.Start(
      [&](const LaserScan& scan) {
        std::lock_guard<std::mutex> lock(mutex);
        if (received.size() < 3 * kScans) received.push_back({scan, clock_.SteadyNow()});
      },
      &error))
      << error;
  for (int i = 0; i < 500; ++i) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (received.size() >= 3 * kScans) break;
    }
    std::this_thread::sleep_for(milliseconds(10));
  }
  laser.Stop();
  EXPECT_FALSE(laser.finished());
  ASSERT_EQ(received.size(), static_cast<size_t>(3 * kScans));
  for (size_t i = 1; i < received.size(); ++i) {
    EXPECT_GT(received[i].scan.stamp, received[i - 1].scan.stamp);
    EXPECT_EQ(received[i].scan.sequence, received[i - 1].scan.sequence + 1);
  }
  // Scan k of pass 1 comes one loop period after scan k of pass 0, and is stamped so.
  EXPECT_EQ(received[kScans + 4].at - received[4].at, timeline->loop_period());
  EXPECT_EQ(received[kScans + 4].scan.stamp - received[4].scan.stamp, timeline->loop_period());
  EXPECT_EQ(laser.Health().state, DeviceState::kOff);  // stopped
}

TEST_F(ReplayDevicesTest, LaserRefusesAMissingFile) {
  ReplayLaserScanner::Options options = LaserOptions(Timeline());
  options.path = path_ + ".missing";
  ReplayLaserScanner laser(options);
  std::string error;
  EXPECT_FALSE(laser.Start([](const LaserScan&) {}, &error));
  EXPECT_NE(error.find(".missing"), std::string::npos) << error;
}

TEST(ReplayCameraConfigTest, ReplayBackendNeedsAFileAndIsBuiltByTheServerWiring) {
  camera::CameraConfig config;
  config.set_backend(camera::CameraConfig::REPLAY);
  std::string error;
  EXPECT_FALSE(camera::ValidateCameraConfig(config, &error));
  EXPECT_NE(error.find("replay.file"), std::string::npos) << error;
  config.mutable_replay()->set_file("run.mostar");
  EXPECT_TRUE(camera::ValidateCameraConfig(config, &error)) << error;
  EXPECT_EQ(camera::MakeStereoCamera(config, &SystemClock::Instance(), &error), nullptr);
  EXPECT_NE(error.find("REPLAY"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::replay
