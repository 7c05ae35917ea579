#include "operator_client/net/client_inbox.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <thread>

#include "common/record/recording_reader.h"
#include "common/time/fake_clock.h"
#include "operator_client/video/test_jpeg.h"

namespace mostar::client {
namespace {

using std::chrono::milliseconds;

CompressedImage Image(Time stamp, int width, int height) {
  CompressedImage image;
  image.stamp = stamp;
  image.format = "jpeg";
  image.data = testing::EncodeJpeg(width, height, 100);
  return image;
}

bool WaitForPairs(const StereoReceiver& video, uint64_t pairs) {
  for (int i = 0; i < 2000 && video.Stats().pairs_decoded < pairs; ++i) {
    std::this_thread::sleep_for(milliseconds(1));
  }
  return video.Stats().pairs_decoded >= pairs;
}

TEST(ClientInboxTest, EveryMessageReachesTheRobotStateTheReceiverAndTheRecording) {
  char dir[] = "/tmp/client_inbox_test_XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string path = std::string(dir) + "/session.mostar";
  FakeClock clock;
  StereoReceiver video(&clock);
  RobotState robot(&clock);
  std::string error;
  auto recorder = record::RecordingWriter::Open(path, {}, {}, clock, &error);
  ASSERT_NE(recorder, nullptr) << error;
  const OperatorNode::Callbacks callbacks =
      InboxCallbacks({"pilot-1", &clock, &video, &robot, recorder.get(), nullptr});

  const Time t = clock.Now();
  LaserScan scan;
  scan.stamp = t;
  scan.ranges_m = {1.f, 2.f};
  callbacks.on_scan(scan);
  RobotHealth health;
  health.estop_engaged = true;
  callbacks.on_health(health);
  callbacks.on_lease(ControlLease{});
  callbacks.on_odometry(Odometry{});
  SonarRanges sonar;
  sonar.ranges.resize(8);
  callbacks.on_sonar(sonar);
  callbacks.on_bumpers(BumperState{});
  callbacks.on_frame_timing({t, t + milliseconds(2), t + milliseconds(3)});
  callbacks.on_image(Eye::kLeft, Image(t, 64, 48));
  callbacks.on_image(Eye::kRight, Image(t, 64, 48));
  ASSERT_TRUE(WaitForPairs(video, 1));

  const RobotSnapshot snapshot = robot.Snapshot();
  ASSERT_TRUE(snapshot.latest_scan.has_value());
  EXPECT_EQ(snapshot.latest_scan->ranges_m, scan.ranges_m);
  EXPECT_TRUE(snapshot.health.has_value());
  EXPECT_TRUE(snapshot.lease.has_value());
  EXPECT_TRUE(snapshot.odometry.has_value());
  ASSERT_TRUE(snapshot.sonar.has_value());
  EXPECT_EQ(snapshot.sonar->ranges.size(), 8u);
  EXPECT_TRUE(snapshot.bumpers.has_value());
  EXPECT_TRUE(robot.TimingOf(t).has_value());

  ASSERT_TRUE(recorder->Close(&error)) << error;
  auto reader = record::RecordingReader::Open(path, &error);
  ASSERT_NE(reader, nullptr) << error;
  std::map<std::string, int> topics;
  record::RecordedMessage message;
  while (reader->Next(&message)) ++topics[record::TopicName(message)];
  EXPECT_EQ(topics["scan"], 1);
  EXPECT_EQ(topics["health"], 1);
  EXPECT_EQ(topics["control/lease"], 1);
  EXPECT_EQ(topics["odom"], 1);
  EXPECT_EQ(topics["sonar"], 1);
  EXPECT_EQ(topics["bumpers"], 1);
  EXPECT_EQ(topics["camera/left"], 1);
  EXPECT_EQ(topics["camera/right"], 1);
  std::remove(path.c_str());
  ::rmdir(dir);
}

TEST(ClientInboxTest, CameraInfoBoundsTheImagesAndOnlyOurOwnPongsCount) {
  FakeClock clock;
  StereoReceiver video(&clock);
  RobotState robot(&clock);
  const OperatorNode::Callbacks callbacks =
      InboxCallbacks({"pilot-1", &clock, &video, &robot, nullptr, nullptr});
  CameraIntrinsicsInfo info;
  info.width_px = 64;
  info.height_px = 48;
  callbacks.on_camera_info(Eye::kLeft, info);
  callbacks.on_camera_info(Eye::kRight, info);
  EXPECT_TRUE(robot.Snapshot().left_intrinsics.has_value());
  const Time t = clock.Now();
  callbacks.on_image(Eye::kLeft, Image(t, 640, 480));  // larger than announced: refused
  callbacks.on_image(Eye::kRight, Image(t, 640, 480));
  EXPECT_EQ(video.Stats().oversized_images, 2u);

  ClockProbe pong;
  pong.sender_id = "observer-2";
  pong.sequence = 1;
  pong.t0 = t;
  pong.t1 = t + milliseconds(1);
  pong.t2 = t + milliseconds(1);
  pong.t3 = t + milliseconds(2);
  callbacks.on_pong(pong);
  EXPECT_EQ(robot.Snapshot().clock.samples, 0u);
  pong.sender_id = "pilot-1";
  callbacks.on_pong(pong);
  EXPECT_EQ(robot.Snapshot().clock.samples, 1u);
}

}  // namespace
}  // namespace mostar::client
