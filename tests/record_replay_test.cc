// Recording and replay across processes: robot_server --record on the simulated robot, the info
// tool on the file, robot_server --replay to a headless client, a truncated file replayed up
// to the damage, and a client rendering the same picture from a replay as it did live.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <thread>
#include <vector>

#include "common/dds/domain.h"
#include "common/record/recording_reader.h"
#include "common/testing/subprocess.h"
#include "common/testing/trace.h"
#include "operator_client/ui/pair_capture.h"

namespace mostar {
namespace {

using testing::ReadTrace;
using testing::Subprocess;

std::string Bin(const char* name) { return std::string(MOSTAR_TEST_BINARY_DIR) + "/" + name; }
std::string Source(const char* path) { return std::string(MOSTAR_TEST_SOURCE_DIR) + "/" + path; }

class RecordReplayTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no X display: run the suite under xvfb-run (as deploy/test.sh does)";
    }
    dir_ = testing::MakeTempDir("mostar_rec_");
    ASSERT_FALSE(dir_.empty());
    domain_ = std::to_string(dds::PerProcessDomainId());
  }
  std::string dir_;
  std::string domain_;
};

TEST_F(RecordReplayTest, RecordedSimulatorSessionReplaysToAClient) {
  const std::string recording = dir_ + "/session.mostar";
  std::string error;
  {
    // Recorded until the laser has streamed 20 scans (its start, with the baud-rate switch, took
    // from 1 s to more than 6 s here) and for at least 6 s; bounded by 60 s.
    Subprocess recorder;
    ASSERT_TRUE(recorder.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--config",
                                Source("deploy/config/server_sim.pbtxt"), "--record", recording,
                                "--trace", dir_ + "/recorded.csv"},
                               dir_ + "/record.log", &error))
        << error;
    const auto started = std::chrono::steady_clock::now();
    const auto elapsed = [&] { return std::chrono::steady_clock::now() - started; };
    const auto scans_seen = [&] {
      size_t n = 0;
      for (const auto& t : ReadTrace(dir_ + "/recorded.csv")) n += t.topic == "scan";
      return n;
    };
    while (elapsed() < std::chrono::seconds(60) &&
           (elapsed() < std::chrono::seconds(6) || scans_seen() < 20)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    recorder.Signal(SIGTERM);
    const auto code = recorder.Wait(std::chrono::seconds(60));
    ASSERT_TRUE(code.has_value());
    ASSERT_EQ(*code, 0) << testing::ReadFile(dir_ + "/record.log");
  }
  {
    Subprocess info;
    ASSERT_TRUE(info.Start({Bin("common/record/mostar_record_info"), recording}, dir_ + "/info.log",
                           &error));
    const auto code = info.Wait(std::chrono::seconds(30));
    ASSERT_TRUE(code.has_value());
    const std::string summary = testing::ReadFile(dir_ + "/info.log");
    EXPECT_EQ(*code, 0) << summary;
    EXPECT_NE(summary.find("scan"), std::string::npos) << summary;
    EXPECT_NE(summary.find("camera/left"), std::string::npos) << summary;
  }
  std::set<int64_t> recorded_frames, recorded_scans;
  for (const auto& t : ReadTrace(dir_ + "/recorded.csv")) {
    if (t.topic == "left") recorded_frames.insert(t.stamp_ns);
    if (t.topic == "scan") recorded_scans.insert(t.stamp_ns);
  }
  ASSERT_GE(recorded_frames.size(), 10u);
  ASSERT_GE(recorded_scans.size(), 10u);

  Subprocess replay;
  ASSERT_TRUE(replay.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--replay",
                            recording, "--loop", "--trace", dir_ + "/replayed.csv"},
                           dir_ + "/replay.log", &error));
  Subprocess client;
  ASSERT_TRUE(client.Start(
      {Bin("operator_client/operator_client"), "--headless", "--domain", domain_, "--role",
       "observer", "--id", "observer", "--duration", "8", "--trace", dir_ + "/client.csv",
       "--screenshot", dir_ + "/replay.png", "--record", dir_ + "/observer.mostar"},
      dir_ + "/client.log", &error));
  const auto client_code = client.Wait(std::chrono::seconds(60));
  replay.Signal(SIGTERM);
  ASSERT_TRUE(replay.Wait(std::chrono::seconds(20)).has_value());
  ASSERT_TRUE(client_code.has_value());
  EXPECT_EQ(*client_code, 0) << testing::ReadFile(dir_ + "/client.log");
  size_t frames = 0, scans = 0;
  for (const auto& t : ReadTrace(dir_ + "/client.csv")) {
    if (t.topic == "left") {
      ++frames;
      EXPECT_TRUE(recorded_frames.count(t.stamp_ns)) << "frame not from the recording";
    }
    if (t.topic == "scan") {
      ++scans;
      EXPECT_TRUE(recorded_scans.count(t.stamp_ns)) << "scan not from the recording";
    }
  }
  EXPECT_GE(frames, 10u);
  EXPECT_GE(scans, 10u);
  EXPECT_FALSE(testing::ReadFile(dir_ + "/replay.png").empty());
  {
    // The observer's own recording of what it received.
    Subprocess info;
    ASSERT_TRUE(info.Start({Bin("common/record/mostar_record_info"), dir_ + "/observer.mostar"},
                           dir_ + "/observer_info.log", &error));
    const auto code = info.Wait(std::chrono::seconds(30));
    ASSERT_TRUE(code.has_value());
    const std::string summary = testing::ReadFile(dir_ + "/observer_info.log");
    EXPECT_EQ(*code, 0) << summary;
    EXPECT_NE(summary.find("camera/left"), std::string::npos) << summary;
    EXPECT_NE(summary.find("scan"), std::string::npos) << summary;
  }

  // Paused replay, stepped from standard input: exactly the stepped records are published.
  {
    Subprocess stepped;
    ASSERT_TRUE(
        stepped.StartWithStdin({Bin("robot_server/robot_server"), "--domain", domain_, "--replay",
                                recording, "--replay-paused", "--trace", dir_ + "/stepped.csv"},
                               dir_ + "/stepped.log", &error));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    ASSERT_TRUE(stepped.WriteStdin("s 40\n"));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    ASSERT_TRUE(stepped.WriteStdin("q\n"));
    const auto code = stepped.Wait(std::chrono::seconds(30));
    ASSERT_TRUE(code.has_value()) << "replay did not quit on 'q'";
    EXPECT_EQ(*code, 0) << testing::ReadFile(dir_ + "/stepped.log");
    // 40 records of every kind were published; the trace holds the images and scans among them.
    size_t traced = 0;
    for (const auto& t : ReadTrace(dir_ + "/stepped.csv")) {
      traced += t.topic == "left" || t.topic == "right" || t.topic == "scan";
    }
    EXPECT_GT(traced, 0u);
    EXPECT_LE(traced, 40u);
  }

  // A truncated copy replays up to the damage and says where it is. It is cut in the middle of
  // the record after the recording's middle scan: the laser may start streaming late in the 6 s
  // (its baud-rate switch took 3.4 s on a busy machine), so half of the bytes can hold no scan.
  uint64_t cut = 0;
  {
    std::unique_ptr<record::RecordingReader> reader =
        record::RecordingReader::Open(recording, &error);
    ASSERT_NE(reader, nullptr) << error;
    std::vector<record::RecordedMessage> messages;
    for (record::RecordedMessage m; reader->Next(&m);) messages.push_back(m);
    std::vector<size_t> scans_at;
    for (size_t i = 0; i < messages.size(); ++i) {
      if (messages[i].kind() == record::RecordKind::kScan) scans_at.push_back(i);
    }
    ASSERT_GE(scans_at.size(), 2u);
    const size_t after_middle_scan = scans_at[scans_at.size() / 2 - 1] + 1;
    ASSERT_LT(after_middle_scan, messages.size());
    const record::RecordedMessage& next = messages[after_middle_scan];
    cut = next.offset + next.size_bytes / 2;
  }
  const std::string data = testing::ReadFile(recording);
  const std::string truncated = dir_ + "/truncated.mostar";
  {
    std::ofstream out(truncated, std::ios::binary);
    out.write(data.data(), static_cast<std::streamsize>(cut));
  }
  Subprocess damaged;
  ASSERT_TRUE(damaged.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--replay",
                             truncated, "--replay-rate", "8", "--trace", dir_ + "/damaged.csv"},
                            dir_ + "/damaged.log", &error));
  const auto code = damaged.Wait(std::chrono::seconds(60));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0);
  const std::string log = testing::ReadFile(dir_ + "/damaged.log");
  EXPECT_NE(log.find("damaged at byte"), std::string::npos) << log;
  size_t replayed = 0;
  for (const auto& t : ReadTrace(dir_ + "/damaged.csv")) replayed += t.topic == "scan";
  EXPECT_GT(replayed, 0u);
  EXPECT_LT(replayed, recorded_scans.size());
}

// Value of "key=<integer>" in a log; -1 when absent.
int64_t ReportValue(const std::string& log, const std::string& key) {
  const size_t at = log.rfind(key + "=");
  if (at == std::string::npos) return -1;
  return std::strtoll(log.c_str() + at + key.size() + 1, nullptr, 10);
}

// Where a capture stamp sits in a recording, in records counted from the start (file order):
// `eyes` = through the later of the pair's two eyes, `scan` = through the first scan stamped at
// or after it, `odometry` = through the first odometry stamped ui::PairCapture::kOdometryAfter
// past it (what the client waits for before rendering the pair).
struct PairRecords {
  int64_t eyes = -1;
  int64_t scan = -1;
  int64_t odometry = -1;
};

PairRecords FindPair(const std::string& path, int64_t stamp_ns, std::vector<int64_t>* left_stamps,
                     std::string* error) {
  PairRecords found;
  auto reader = record::RecordingReader::Open(path, error);
  if (!reader) return found;
  record::RecordedMessage m;
  int eyes_seen = 0;
  for (int64_t count = 1; reader->Next(&m); ++count) {
    if (const auto* image = std::get_if<record::RecordedImage>(&m.payload)) {
      const int64_t stamp = ToUnixNanos(image->image.stamp);
      if (image->eye == Eye::kLeft && left_stamps != nullptr) left_stamps->push_back(stamp);
      if (stamp == stamp_ns && ++eyes_seen == 2) found.eyes = count;
    } else if (const auto* scan = std::get_if<LaserScan>(&m.payload)) {
      if (found.eyes > 0 && found.scan < 0 && ToUnixNanos(scan->stamp) >= stamp_ns) {
        found.scan = count;
      }
    } else if (const auto* odometry = std::get_if<Odometry>(&m.payload)) {
      if (found.eyes > 0 && found.odometry < 0 &&
          odometry->stamp >= FromUnixNanos(stamp_ns) + ui::PairCapture::kOdometryAfter) {
        found.odometry = count;
      }
    }
  }
  return found;
}

struct PixelDiff {
  double identical_fraction = 0;
  int max_abs = 0;
};

PixelDiff Compare(const cv::Mat& a, const cv::Mat& b) {
  PixelDiff d;
  if (a.size() != b.size() || a.type() != b.type() || a.empty()) return {0, 255};
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  std::vector<cv::Mat> channels;
  cv::split(diff, channels);
  cv::Mat per_pixel = channels[0].clone();
  for (size_t c = 1; c < channels.size(); ++c) per_pixel = cv::max(per_pixel, channels[c]);
  double max_value = 0;
  cv::minMaxLoc(per_pixel, nullptr, &max_value);
  d.max_abs = static_cast<int>(max_value);
  d.identical_fraction = 1.0 - static_cast<double>(cv::countNonZero(per_pixel)) /
                                   static_cast<double>(per_pixel.total());
  return d;
}

// The client's picture of one stereo pair is a function of the recorded data only: rendered
// live against the simulated robot while the robot records, and again from robot_server
// --replay of that recording, the two PNGs are identical. The client's --capture-* mode makes
// this deterministic (the pair is rendered once the scans around it are in and its edge result
// is ready; --no-hud hides the changing rates). The replay is paused and stepped record by
// record count, so the pair is the newest one when the client latches it, however slow the
// machine. A neighbouring pair rendered from the same replay differs, so the comparison can
// fail.
TEST_F(RecordReplayTest, ReplayRendersTheSamePictureAsLive) {
  const std::string recording = dir_ + "/live.mostar";
  const std::string client_config = Source("deploy/config/client_sim.pbtxt");
  std::string error;
  int64_t stamp = -1;
  {
    Subprocess robot;
    ASSERT_TRUE(robot.Start(
        {Bin("robot_server/robot_server"), "--domain", domain_, "--config",
         Source("deploy/config/server_sim.pbtxt"), "--record", recording, "--duration", "60"},
        dir_ + "/live_robot.log", &error))
        << error;
    // The captured pair waits at most 2 s for its scan (PairCapture::kScanWait); the emulated
    // LMS200 starts at 9600 Bd and switches, which under load takes longer: start the client
    // once it streams.
    ASSERT_TRUE(
        testing::WaitForText(dir_ + "/live_robot.log", "streaming at", std::chrono::seconds(50)))
        << testing::ReadFile(dir_ + "/live_robot.log");
    Subprocess client;
    ASSERT_TRUE(client.Start(
        {Bin("operator_client/operator_client"), "--headless", "--domain", domain_, "--config",
         client_config, "--role", "observer", "--id", "observer", "--capture-after", "60",
         "--no-hud", "--duration", "40", "--screenshot", dir_ + "/live.png"},
        dir_ + "/live_client.log", &error))
        << error;
    const auto code = client.Wait(std::chrono::seconds(60));
    robot.Signal(SIGTERM);
    ASSERT_TRUE(robot.Wait(std::chrono::seconds(20)).has_value());
    ASSERT_TRUE(code.has_value());
    const std::string log = testing::ReadFile(dir_ + "/live_client.log");
    ASSERT_EQ(*code, 0) << log;
    stamp = ReportValue(log, "captured_stamp_ns");
    ASSERT_GT(stamp, 0) << log;
  }
  std::vector<int64_t> left_stamps;
  const PairRecords target = FindPair(recording, stamp, &left_stamps, &error);
  ASSERT_GT(target.eyes, 0) << "the captured pair is not in the recording " << error;
  ASSERT_GT(target.scan, target.eyes) << "no scan after the captured pair in the recording";
  ASSERT_GT(target.odometry, target.eyes) << "no odometry after the captured pair";
  // A pair about a second earlier, for the negative check.
  const auto it = std::find(left_stamps.begin(), left_stamps.end(), stamp);
  ASSERT_GE(it - left_stamps.begin(), 25);
  const int64_t other_stamp = *(it - 25);
  const PairRecords other = FindPair(recording, other_stamp, nullptr, &error);
  ASSERT_GT(other.eyes, 0);
  ASSERT_LT(other.scan, target.eyes) << "pairs too close for separate steps";

  Subprocess replay;
  ASSERT_TRUE(replay.StartWithStdin({Bin("robot_server/robot_server"), "--domain", domain_,
                                     "--replay", recording, "--replay-paused"},
                                    dir_ + "/replay_robot.log", &error))
      << error;
  Subprocess same, earlier;
  const std::vector<std::string> client = {Bin("operator_client/operator_client"),
                                           "--headless",
                                           "--domain",
                                           domain_,
                                           "--config",
                                           client_config,
                                           "--role",
                                           "observer",
                                           "--no-hud",
                                           "--duration",
                                           "40"};
  auto with = [&](std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
  };
  ASSERT_TRUE(same.Start(with(client, {"--id", "observer", "--capture-stamp", std::to_string(stamp),
                                       "--screenshot", dir_ + "/replay.png"}),
                         dir_ + "/replay_client.log", &error))
      << error;
  ASSERT_TRUE(earlier.Start(
      with(client, {"--id", "observer-2", "--capture-stamp", std::to_string(other_stamp),
                    "--screenshot", dir_ + "/earlier.png"}),
      dir_ + "/earlier_client.log", &error))
      << error;
  std::this_thread::sleep_for(std::chrono::seconds(4));  // discovery: the video is volatile
  // Each pair is published last (the client latches it), then up to the scan and the odometry
  // after it.
  const int64_t target_settled = std::max(target.scan, target.odometry);
  const int64_t steps[] = {other.eyes, other.scan - other.eyes, target.eyes - other.scan,
                           target_settled - target.eyes};
  for (const int64_t n : steps) {
    ASSERT_TRUE(replay.WriteStdin("s " + std::to_string(n) + "\n"));
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  }
  const auto same_code = same.Wait(std::chrono::seconds(45));
  const auto earlier_code = earlier.Wait(std::chrono::seconds(45));
  ASSERT_TRUE(replay.WriteStdin("q\n"));
  ASSERT_TRUE(replay.Wait(std::chrono::seconds(20)).has_value());
  ASSERT_TRUE(same_code.has_value());
  ASSERT_TRUE(earlier_code.has_value());
  const std::string same_log = testing::ReadFile(dir_ + "/replay_client.log");
  ASSERT_EQ(*same_code, 0) << same_log;
  ASSERT_EQ(*earlier_code, 0) << testing::ReadFile(dir_ + "/earlier_client.log");
  EXPECT_EQ(ReportValue(same_log, "captured_stamp_ns"), stamp) << same_log;

  const cv::Mat live = cv::imread(dir_ + "/live.png", cv::IMREAD_COLOR);
  const cv::Mat replayed = cv::imread(dir_ + "/replay.png", cv::IMREAD_COLOR);
  const cv::Mat neighbour = cv::imread(dir_ + "/earlier.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(live.empty());
  ASSERT_FALSE(replayed.empty());
  ASSERT_FALSE(neighbour.empty());
  // A real picture (camera image and overlay), not a blank window.
  cv::Scalar mean, stddev;
  cv::meanStdDev(live, mean, stddev);
  EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 30.0);
  const PixelDiff d = Compare(live, replayed);
  std::cout << "live vs replay: " << 100 * d.identical_fraction << " % identical, max diff "
            << d.max_abs << "\n";
  // Same bytes in, same decoder, same scan, same renderer: identical.
  EXPECT_EQ(d.max_abs, 0) << 100 * (1 - d.identical_fraction) << " % of pixels differ";
  const PixelDiff n = Compare(live, neighbour);
  std::cout << "live vs a pair 25 earlier: " << 100 * n.identical_fraction << " % identical\n";
  EXPECT_LT(n.identical_fraction, 0.99) << "a different pair should look different";
}

}  // namespace
}  // namespace mostar
