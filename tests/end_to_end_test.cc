// The walking skeleton end to end: the real robot_server and a headless operator_client on
// loopback DDS with a private domain id. Checks that frames, scans and commands flow both ways
// with matching stamps and sequence numbers, that the robot moves under the pilot's command,
// and that both programs shut down cleanly on SIGTERM.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/domain.h"
#include "common/testing/subprocess.h"
#include "common/testing/trace.h"
#include "common/time/fake_clock.h"
#include "robot_server/testpattern/test_pattern.h"

namespace mostar {
namespace {

using testing::Subprocess;

using testing::ReadTrace;

std::string Bin(const char* name) { return std::string(MOSTAR_TEST_BINARY_DIR) + "/" + name; }
std::string Source(const char* path) { return std::string(MOSTAR_TEST_SOURCE_DIR) + "/" + path; }

// What the screenshot of a working pipeline shows and a blank or video-only frame does not.
struct ScreenshotContent {
  double grey_stddev = 0;  // 0 for a uniform image
  // Pixels in the lower half in the AR overlay's distance colours (walls, rays, circles, labels:
  // red 0 deg - yellow 60 deg - green 120 deg, strongly saturated and bright). The test
  // pattern's floor, walls and text are greys and pale colours; the HUD sits in the top left.
  int overlay_pixels = 0;
};

ScreenshotContent Analyse(const cv::Mat& bgr) {
  ScreenshotContent content;
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(grey, mean, stddev);
  content.grey_stddev = stddev[0];
  cv::Mat hsv;  // OpenCV 8-bit hue: degrees / 2
  cv::cvtColor(bgr(cv::Rect(0, bgr.rows / 2, bgr.cols, bgr.rows - bgr.rows / 2)), hsv,
               cv::COLOR_BGR2HSV);
  cv::Mat red_to_green, red_wrap;
  cv::inRange(hsv, cv::Scalar(0, 150, 100), cv::Scalar(65, 255, 255), red_to_green);
  cv::inRange(hsv, cv::Scalar(170, 150, 100), cv::Scalar(180, 255, 255), red_wrap);
  content.overlay_pixels = cv::countNonZero(red_to_green) + cv::countNonZero(red_wrap);
  return content;
}

// Share of the lower half in overlay colours that a drawn overlay exceeds. Measured on this
// test's screenshots: 23% and 41% (the distance-coloured wall band fills the lower half as the
// robot nears the wall); the same run with walls, rays, circles, labels and vision switched off
// in the client config: 0%. The laser points alone (a dotted line across) would be about 1.1%.
constexpr double kMinOverlayShare = 0.02;

// The check itself must reject what a broken pipeline would save: a blank frame and the
// camera's picture without the overlay.
TEST(ScreenshotContentTest, RejectsBlankAndVideoOnlyFrames) {
  const cv::Mat blank(480, 640, CV_8UC3, cv::Scalar(0, 0, 0));
  EXPECT_LT(Analyse(blank).grey_stddev, 1.0);
  EXPECT_EQ(Analyse(blank).overlay_pixels, 0);

  FakeClock clock;
  testpattern::KinematicRobot robot(testpattern::RoomOptions{}, &clock);
  testpattern::TestPatternCamera camera(&robot, 640, 480, 30, &clock);
  std::string error;
  ASSERT_TRUE(camera.Open(&error)) << error;
  camera::StereoImagePair pair;
  ASSERT_TRUE(camera.Grab(std::chrono::seconds(1), &pair).ok());
  // As the client shows it: through JPEG at the server's quality.
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", pair.left, jpeg, {cv::IMWRITE_JPEG_QUALITY, 80}));
  const cv::Mat video_only = cv::imdecode(jpeg, cv::IMREAD_COLOR);
  const ScreenshotContent content = Analyse(video_only);
  EXPECT_GT(content.grey_stddev, 10.0);  // the pattern alone is not uniform ...
  EXPECT_LT(content.overlay_pixels, kMinOverlayShare * 640 * 240);  // ... but has no overlay
}

class EndToEndTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no X display: run the suite under xvfb-run (as .ci/run does)";
    }
    dir_ = testing::MakeTempDir("mostar_e2e_");
    ASSERT_FALSE(dir_.empty());
    domain_ = std::to_string(dds::PerProcessDomainId());
  }
  // Runs robot_server with `server_config` and a headless observer (edge processing off) for
  // 8 s with `display_args`, writing a screenshot to `screenshot`; both must end cleanly.
  // Returns the observer's log (its report: line).
  std::string RunObserver(const std::string& server_config,
                          const std::vector<std::string>& display_args,
                          const std::string& screenshot) {
    Subprocess server;
    std::string error;
    EXPECT_TRUE(server.Start(
        {Bin("robot_server/robot_server"), "--domain", domain_, "--config", server_config},
        dir_ + "/server.log", &error))
        << error;
    Subprocess client;
    const std::string config = dir_ + "/client.pbtxt";
    {
      std::ofstream out(config);
      out << "calibration_profile: \"" << Source("deploy/config/calibration_sim.pbtxt")
          << "\"\nvision_enabled: false\n";
    }
    std::vector<std::string> args = {Bin("operator_client/operator_client"),
                                     "--headless",
                                     "--domain",
                                     domain_,
                                     "--id",
                                     "observer",
                                     "--role",
                                     "observer",
                                     "--config",
                                     config,
                                     "--duration",
                                     "8",
                                     "--screenshot",
                                     screenshot};
    args.insert(args.end(), display_args.begin(), display_args.end());
    EXPECT_TRUE(client.Start(args, dir_ + "/client.log", &error)) << error;
    const std::optional<int> client_exit = client.Wait(std::chrono::seconds(90));
    EXPECT_TRUE(client_exit.has_value()) << "client hung";
    server.Signal(SIGTERM);
    EXPECT_TRUE(server.Wait(std::chrono::seconds(20)).has_value()) << "server did not stop";
    const std::string report = testing::ReadFile(dir_ + "/client.log");
    EXPECT_EQ(client_exit.value_or(-1), 0) << report;
    return report;
  }
  // The integer after " key=" in `report`; -1 (and a failure) when missing.
  static int Value(const std::string& report, const std::string& key) {
    const size_t at = report.find(" " + key + "=");
    EXPECT_NE(at, std::string::npos) << key << " missing in " << report;
    return at == std::string::npos ? -1 : std::stoi(report.substr(at + key.size() + 2));
  }

  std::string dir_;
  std::string domain_;
};

TEST_F(EndToEndTest, FramesScansAndCommandsFlowBothWays) {
  Subprocess server;
  std::string error;
  ASSERT_TRUE(server.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--config",
                            Source("deploy/config/server_sim.pbtxt"), "--source", "test_pattern",
                            "--trace", dir_ + "/server.csv"},
                           dir_ + "/server.log", &error))
      << error;
  Subprocess client;
  ASSERT_TRUE(client.Start({Bin("operator_client/operator_client"), "--headless", "--domain",
                            domain_, "--id", "operator", "--duration", "6", "--drive", "0.3,0",
                            "--trace", dir_ + "/client.csv", "--screenshot", dir_ + "/client.png"},
                           dir_ + "/client.log", &error))
      << error;
  const std::optional<int> client_exit = client.Wait(std::chrono::seconds(60));
  ASSERT_TRUE(client_exit.has_value()) << "client hung";
  EXPECT_EQ(*client_exit, 0) << testing::ReadFile(dir_ + "/client.log");
  server.Signal(SIGTERM);
  const std::optional<int> server_exit = server.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(server_exit.has_value()) << "server did not stop on SIGTERM";
  EXPECT_EQ(*server_exit, 0) << testing::ReadFile(dir_ + "/server.log");

  const auto published = ReadTrace(dir_ + "/server.csv");
  const auto received = ReadTrace(dir_ + "/client.csv");
  std::map<std::string, std::set<int64_t>> published_stamps;
  std::set<uint64_t> accepted_commands;
  uint64_t max_odom_x_mm = 0;
  for (const auto& t : published) {
    published_stamps[t.topic].insert(t.stamp_ns);
    if (t.topic == "command") accepted_commands.insert(t.sequence);
    if (t.topic == "odom_x_mm") max_odom_x_mm = std::max(max_odom_x_mm, t.sequence);
  }
  std::map<std::string, int> received_count;
  std::set<int64_t> left_stamps, right_stamps;
  std::set<uint64_t> sent_commands;
  uint64_t acked_sequence = 0;
  for (const auto& t : received) {
    ++received_count[t.topic];
    if (t.topic == "left" || t.topic == "right" || t.topic == "scan") {
      EXPECT_TRUE(published_stamps[t.topic].count(t.stamp_ns))
          << t.topic << " stamp " << t.stamp_ns << " was never published";
    }
    if (t.topic == "left") left_stamps.insert(t.stamp_ns);
    if (t.topic == "right") right_stamps.insert(t.stamp_ns);
    if (t.topic == "command") sent_commands.insert(t.sequence);
    if (t.topic == "health") acked_sequence = std::max(acked_sequence, t.sequence);
  }
  // Video, scans and health reached the client.
  EXPECT_GE(received_count["left"], 30);
  EXPECT_GE(received_count["right"], 30);
  EXPECT_GE(received_count["scan"], 10);
  EXPECT_GE(received_count["health"], 3);
  // Both eyes of a pair carry the same capture stamp.
  size_t paired = 0;
  for (int64_t s : left_stamps) paired += right_stamps.count(s);
  EXPECT_GE(paired, left_stamps.size() * 8 / 10);
  // Commands reached the robot: every accepted sequence was sent, and health echoes one.
  ASSERT_GE(accepted_commands.size(), 20u);
  for (uint64_t seq : accepted_commands) EXPECT_TRUE(sent_commands.count(seq)) << seq;
  EXPECT_TRUE(sent_commands.count(acked_sequence)) << acked_sequence;
  // The robot drove forward under the command (0.3 m/s for several seconds).
  EXPECT_GT(max_odom_x_mm, 500u);
  // The client rendered and saved a frame of the camera's size (mono-left, default
  // calibration 640x480) with the pattern and the AR overlay in it.
  const cv::Mat screenshot = cv::imread(dir_ + "/client.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(screenshot.empty()) << "no decodable PNG at " << dir_ << "/client.png";
  EXPECT_EQ(screenshot.cols, 640);
  EXPECT_EQ(screenshot.rows, 480);
  const ScreenshotContent content = Analyse(screenshot);
  EXPECT_GT(content.grey_stddev, 10.0) << "a uniform frame: no video was drawn";
  EXPECT_GE(content.overlay_pixels, kMinOverlayShare * screenshot.cols * (screenshot.rows / 2))
      << "no AR overlay in distance colours in the lower half of " << dir_ << "/client.png";
  const std::string report = testing::ReadFile(dir_ + "/client.log");
  EXPECT_NE(report.find("report: rendered_frames="), std::string::npos);
  // The latency trace has every stage, robot side (camera timing topic) included: the stages
  // add up to the total, and none is negative beyond the clock offset's error.
  auto value = [&](const std::string& key) {
    const size_t at = report.find(" " + key + "=");
    EXPECT_NE(at, std::string::npos) << key << " missing in the report";
    return at == std::string::npos ? -1e9 : std::stod(report.substr(at + key.size() + 2));
  };
  for (const char* stage : {"encoded", "written", "received", "queued", "decoded", "picked",
                            "vision", "started", "drawn", "presented"}) {
    EXPECT_GE(value(std::string("latency_") + stage + "_ms_p50"), -1.0) << stage;
  }
  EXPECT_GT(value("latency_total_ms_p50"), 0.0);
  EXPECT_NEAR(value("latency_unexplained_ms_p50"), 0.0, 0.5) << "a stage without its stamp";
}

// A console started before the robot joins DDS again, as a new participant, while nothing of
// the robot matches (RejoinPolicy: here after 1 s, then 2, then 4; the same path gets a console
// out of a DDS Security handshake that never ends), and once the robot is up, it sees it and
// drives it through the participant it joined with last.
TEST_F(EndToEndTest, AConsoleStartedBeforeTheRobotJoinsAgainAndDrivesOnceItComes) {
  Subprocess client;
  std::string error;
  ASSERT_TRUE(client.Start({Bin("operator_client/operator_client"), "--headless", "--domain",
                            domain_, "--id", "operator", "--duration", "14", "--drive", "0.3,0",
                            "--rejoin-after", "1", "--trace", dir_ + "/client.csv"},
                           dir_ + "/client.log", &error))
      << error;
  std::this_thread::sleep_for(std::chrono::milliseconds(4500));
  Subprocess server;
  ASSERT_TRUE(server.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--config",
                            Source("deploy/config/server_sim.pbtxt"), "--source", "test_pattern",
                            "--trace", dir_ + "/server.csv"},
                           dir_ + "/server.log", &error))
      << error;
  const std::optional<int> client_exit = client.Wait(std::chrono::seconds(60));
  ASSERT_TRUE(client_exit.has_value()) << "client hung";
  const std::string log = testing::ReadFile(dir_ + "/client.log");
  EXPECT_EQ(*client_exit, 0) << log;
  server.Signal(SIGTERM);
  const std::optional<int> server_exit = server.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(server_exit.has_value()) << "server did not stop on SIGTERM";

  // Joined again at 1 s and 3 s without the robot (then it waits 4 s: the robot comes first).
  size_t joins = 0;
  for (size_t at = log.find("joining DDS again"); at != std::string::npos;
       at = log.find("joining DDS again", at + 1)) {
    ++joins;
  }
  EXPECT_GE(joins, 2u) << log;
  EXPECT_EQ(log.find("cannot join DDS again"), std::string::npos) << log;
  // The robot accepted the console's commands and drove under them.
  std::set<uint64_t> accepted;
  uint64_t max_odom_x_mm = 0;
  for (const auto& t : ReadTrace(dir_ + "/server.csv")) {
    if (t.topic == "command") accepted.insert(t.sequence);
    if (t.topic == "odom_x_mm") max_odom_x_mm = std::max(max_odom_x_mm, t.sequence);
  }
  EXPECT_GE(accepted.size(), 20u) << testing::ReadFile(dir_ + "/server.log");
  EXPECT_GT(max_odom_x_mm, 300u);
  int left = 0;
  for (const auto& t : ReadTrace(dir_ + "/client.csv")) left += t.topic == "left" ? 1 : 0;
  EXPECT_GE(left, 30) << "video after the join";
}

// The simulated robot before the closed glass door (deploy/scenes/glass_door.pbtxt): the laser
// measures the wall behind the glass, the sonar belt hears the door, and the console draws the
// forward sonar sectors outlined in magenta as echoes the laser does not see.
TEST_F(EndToEndTest, SonarSectorsShowTheGlassDoorTheLaserSeesThrough) {
  Subprocess server;
  std::string error;
  ASSERT_TRUE(server.Start(
      {Bin("robot_server/robot_server"), "--domain", domain_, "--config",
       Source("deploy/config/server_sim.pbtxt"), "--sim", Source("deploy/scenes/glass_door.pbtxt")},
      dir_ + "/server.log", &error))
      << error;
  // The captured pair waits at most 2 s for its scan (PairCapture::kScanWait); under load the
  // emulated LMS200's baud switch alone can take longer, so the client starts once it streams.
  ASSERT_TRUE(testing::WaitForText(dir_ + "/server.log", "streaming at", std::chrono::seconds(60)))
      << "the LMS200 never streamed:\n"
      << testing::ReadFile(dir_ + "/server.log");
  Subprocess client;
  // Edge processing off: its magenta dots would count as sonar outlines.
  const std::string config = dir_ + "/client.pbtxt";
  {
    std::ofstream out(config);
    out << "calibration_profile: \"" << Source("deploy/config/calibration_sim.pbtxt")
        << "\"\nvision_enabled: false\n";
  }
  ASSERT_TRUE(client.Start({Bin("operator_client/operator_client"), "--headless", "--domain",
                            domain_, "--id", "observer", "--role", "observer", "--config", config,
                            "--capture-after", "45", "--screenshot", dir_ + "/sonar.png"},
                           dir_ + "/client.log", &error))
      << error;
  const std::optional<int> client_exit = client.Wait(std::chrono::seconds(90));
  ASSERT_TRUE(client_exit.has_value()) << "client hung";
  server.Signal(SIGTERM);
  ASSERT_TRUE(server.Wait(std::chrono::seconds(20)).has_value()) << "server did not stop";
  const std::string report = testing::ReadFile(dir_ + "/client.log");
  ASSERT_EQ(*client_exit, 0) << report;
  auto value = [&](const std::string& key) {
    const size_t at = report.find(" " + key + "=");
    EXPECT_NE(at, std::string::npos) << key << " missing in " << report;
    return at == std::string::npos ? -1 : std::stoi(report.substr(at + key.size() + 2));
  };
  EXPECT_GE(value("sonar_echoes"), 3) << "the belt hears the room";
  EXPECT_GE(value("sonar_unseen"), 1) << "the glass door: sonar echo, no laser point";
  const cv::Mat shot = cv::imread(dir_ + "/sonar.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty());
  cv::Mat magenta;  // the outline colour (255, 0, 255), blended a little by the line edges
  cv::inRange(shot(cv::Rect(0, shot.rows / 2, shot.cols, shot.rows - shot.rows / 2)),
              cv::Scalar(200, 0, 200), cv::Scalar(255, 90, 255), magenta);
  EXPECT_GE(cv::countNonZero(magenta), 100) << "no magenta sonar outline in " << dir_;
}

// The simulator at the cameras' native 1280x960 (deploy/config/server_sim_1280.pbtxt) and a
// client whose window shows one eye at 640x480 (mono-left, the 640x480 calibration profile):
// the left eye is decoded at 1/2, the right one not at all, and the overlay is drawn.
TEST_F(EndToEndTest, TheNativeResolutionIsDecodedAtTheWindowSizeAndMonoDecodesOneEye) {
  const std::string report = RunObserver(Source("deploy/config/server_sim_1280.pbtxt"),
                                         {"--display", "mono-left"}, dir_ + "/native.png");
  auto value = [&](const std::string& key) { return Value(report, key); };
  const int pairs = value("pairs_decoded");
  EXPECT_GE(pairs, 30) << report;
  EXPECT_EQ(value("left_decodes"), pairs) << report;
  EXPECT_EQ(value("right_decodes"), 0) << "mono-left without edge processing: " << report;
  // Every decode after the first frames (before the window size reached the decoder) is scaled.
  EXPECT_GE(value("scaled_decodes"), pairs - 5) << report;
  EXPECT_EQ(value("oversized_images"), 0) << report;
  EXPECT_EQ(value("broken_images"), 0) << report;
  const cv::Mat shot = cv::imread(dir_ + "/native.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty()) << "no screenshot in " << dir_;
  EXPECT_EQ(shot.cols, 640);
  EXPECT_EQ(shot.rows, 480);
  const ScreenshotContent content = Analyse(shot);
  EXPECT_GT(content.grey_stddev, 10.0) << "a uniform frame: no video was drawn";
  EXPECT_GE(content.overlay_pixels, kMinOverlayShare * shot.cols * (shot.rows / 2))
      << "no AR overlay in the lower half of " << dir_ << "/native.png";
}

// Codec H264: the console decodes both eyes' streams and shows them with the overlay; a
// console that joins a running stream starts at the IDR the robot sends when it matches.
TEST_F(EndToEndTest, H264StreamsAreDecodedAndShownWithTheOverlay) {
  const std::string report =
      RunObserver(Source("deploy/config/server_sim_h264.pbtxt"), {}, dir_ + "/h264.png");
  auto value = [&](const std::string& key) { return Value(report, key); };
  EXPECT_GE(value("video_frames"), 30) << report;
  EXPECT_GE(value("pairs_decoded"), 30) << report;
  EXPECT_EQ(value("video_errors"), 0) << report;
  EXPECT_EQ(value("broken_images"), 0) << report;
  // Loopback loses nothing, and the join IDR comes first or soon after.
  EXPECT_EQ(value("video_gaps"), 0) << report;
  EXPECT_LE(value("video_skipped"), 15) << report;
  const cv::Mat shot = cv::imread(dir_ + "/h264.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty()) << "no screenshot in " << dir_;
  const ScreenshotContent content = Analyse(shot);
  EXPECT_GT(content.grey_stddev, 10.0) << "a uniform frame: no video was drawn";
  EXPECT_GE(content.overlay_pixels, kMinOverlayShare * shot.cols * (shot.rows / 2))
      << "no AR overlay in the lower half of " << dir_ << "/h264.png";
  const std::string server_log = testing::ReadFile(dir_ + "/server.log");
  EXPECT_NE(server_log.find("keyframe requested"), std::string::npos) << server_log;
}

// One copy up the robot's uplink (docs/networking.md): the pilot takes the H.264 stream through
// mostar_relay on another domain (--video-via-relay) while its commands go to the robot
// directly. The robot's only reader of the stream is the relay; the relay's own receive reports
// and the pilot's, which the relay passes on, drive the robot's rate control.
TEST_F(EndToEndTest, APilotTakesTheVideoThroughTheRelaySoTheRobotSendsItOnce) {
  const std::optional<int> video_domain =
      dds::AcquireUnusedDomainId(100, 132, std::stoi(domain_) - 100 + 1);
  ASSERT_TRUE(video_domain.has_value());
  Subprocess server, relay, pilot;
  std::string error;
  ASSERT_TRUE(
      server.Start({Bin("robot_server/robot_server"), "--domain", domain_, "--config",
                    Source("deploy/config/server_sim_h264.pbtxt"), "--trace", dir_ + "/server.csv"},
                   dir_ + "/server.log", &error))
      << error;
  ASSERT_TRUE(
      relay.Start({Bin("operator_client/relay/mostar_relay"), "--robot-domain", domain_,
                   "--observer-domain", std::to_string(*video_domain), "--stats-period-s", "1"},
                  dir_ + "/relay.log", &error))
      << error;
  const std::string config = dir_ + "/client.pbtxt";
  {
    std::ofstream out(config);
    out << "calibration_profile: \"" << Source("deploy/config/calibration_sim.pbtxt")
        << "\"\nvision_enabled: false\n";
  }
  ASSERT_TRUE(
      pilot.Start({Bin("operator_client/operator_client"), "--headless", "--domain", domain_,
                   "--video-via-relay", "--video-domain", std::to_string(*video_domain), "--id",
                   "operator", "--config", config, "--duration", "8", "--drive", "0.3,0"},
                  dir_ + "/client.log", &error))
      << error;
  const std::optional<int> pilot_exit = pilot.Wait(std::chrono::seconds(90));
  ASSERT_TRUE(pilot_exit.has_value()) << "pilot hung";
  relay.Signal(SIGTERM);
  server.Signal(SIGTERM);
  EXPECT_TRUE(relay.Wait(std::chrono::seconds(20)).has_value()) << "relay did not stop";
  EXPECT_TRUE(server.Wait(std::chrono::seconds(20)).has_value()) << "server did not stop";
  const std::string report = testing::ReadFile(dir_ + "/client.log");
  const std::string relay_log = testing::ReadFile(dir_ + "/relay.log");
  const std::string server_log = testing::ReadFile(dir_ + "/server.log");
  EXPECT_EQ(pilot_exit.value_or(-1), 0) << report;
  // The pilot saw the video, through the relay ...
  EXPECT_GE(Value(report, "video_frames"), 30) << report;
  EXPECT_GE(Value(report, "pairs_decoded"), 30) << report;
  EXPECT_EQ(Value(report, "video_errors"), 0) << report;
  EXPECT_NE(relay_log.find("rt/mostar/camera/stereo/h264: in="), std::string::npos) << relay_log;
  EXPECT_NE(relay_log.find("observers=1"), std::string::npos) << relay_log;
  // ... and drove the robot directly: the robot moved.
  uint64_t max_odom_x_mm = 0;
  for (const auto& t : ReadTrace(dir_ + "/server.csv")) {
    if (t.topic == "odom_x_mm") max_odom_x_mm = std::max(max_odom_x_mm, t.sequence);
  }
  EXPECT_GT(max_odom_x_mm, 500u) << report;
  // One copy: the robot never had a second reader of the stream.
  const std::string readers = "readers of the H.264 stream: ";
  int max_readers = 0;
  for (size_t at = server_log.find(readers); at != std::string::npos;
       at = server_log.find(readers, at + 1)) {
    max_readers = std::max(max_readers, std::stoi(server_log.substr(at + readers.size())));
  }
  EXPECT_EQ(max_readers, 1) << server_log;
  // The relay reported its own arrivals and passed the pilot's (the lease holder's) reports on:
  // the robot's rate control heard two viewers, the relay and the pilot.
  const std::string reports = "video_feedback (to the robot): reports=";
  const size_t at = relay_log.rfind(reports);
  ASSERT_NE(at, std::string::npos) << relay_log;
  EXPECT_GE(std::stoi(relay_log.substr(at + reports.size())), 20) << relay_log;
  const std::string pilot_reports = "pilot_reports=";
  const size_t pilot_at = relay_log.find(pilot_reports, at);
  ASSERT_NE(pilot_at, std::string::npos) << relay_log;
  EXPECT_GE(std::stoi(relay_log.substr(pilot_at + pilot_reports.size())), 20) << relay_log;
  EXPECT_NE(server_log.find("2 viewers reporting"), std::string::npos) << server_log;
}

TEST_F(EndToEndTest, BadFlagsAndConfigGiveClearErrors) {
  Subprocess server;
  std::string error;
  ASSERT_TRUE(server.Start({Bin("robot_server/robot_server"), "--domain", "999"},
                           dir_ + "/bad_domain.log", &error));
  std::optional<int> code = server.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_NE(*code, 0);
  EXPECT_NE(testing::ReadFile(dir_ + "/bad_domain.log").find("--domain"), std::string::npos);

  {
    std::ofstream bad(dir_ + "/bad.pbtxt");
    bad << "robot_id: \"x\"\ncontrol_period_s: 7\n";
  }
  Subprocess server2;
  ASSERT_TRUE(server2.Start({Bin("robot_server/robot_server"), "--config", dir_ + "/bad.pbtxt"},
                            dir_ + "/bad_config.log", &error));
  code = server2.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 2);
  const std::string log = testing::ReadFile(dir_ + "/bad_config.log");
  EXPECT_NE(log.find("bad.pbtxt:2:1: control_period_s: 7 is outside"), std::string::npos) << log;

  Subprocess client;
  ASSERT_TRUE(
      client.Start({Bin("operator_client/operator_client"), "--display", "hologram", "--headless"},
                   dir_ + "/bad_display.log", &error));
  code = client.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 2);
  EXPECT_NE(testing::ReadFile(dir_ + "/bad_display.log").find("unknown display mode"),
            std::string::npos);
}

}  // namespace
}  // namespace mostar
