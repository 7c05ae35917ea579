// The video ack-clock with real DDS participants on loopback: a net_probe subprocess is the
// observer that stops acknowledging (SIGSTOP); an in-process reader is everyone else. And the
// network health saying whether DDS Security is off.
#include "robot_server/node/robot_node.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include "common/dds/domain.h"
#include "common/dds/topics.h"
#include "common/testing/dds_profiles.h"
#include "common/testing/subprocess.h"

namespace mostar::server {
namespace {

using ImageType = sensor_msgs::msg::dds_::CompressedImage_PubSubType;

CompressedStereoPair Pair(uint64_t sequence) {
  CompressedStereoPair pair;
  pair.sequence = sequence;
  for (CompressedImage* image : {&pair.left, &pair.right}) {
    image->stamp = SystemClock::Instance().Now();
    image->format = "jpeg";
    image->data.assign(20000, static_cast<uint8_t>(sequence));
  }
  pair.left.frame_id = "camera_left";
  pair.right.frame_id = "camera_right";
  return pair;
}

std::unique_ptr<dds::Participant> MakeParticipant(const std::string& name) {
  dds::ParticipantOptions options;
  options.domain_id = dds::PerProcessDomainId();
  options.name = name;
  std::string error;
  auto participant = dds::Participant::Create(options, &error);
  EXPECT_NE(participant, nullptr) << error;
  return participant;
}

// Publishes a pair every 33 ms for `duration`; returns how many went out.
int PublishFor(RobotNode* node, uint64_t* sequence, std::chrono::milliseconds duration) {
  int sent = 0;
  const auto end = std::chrono::steady_clock::now() + duration;
  while (std::chrono::steady_clock::now() < end) {
    if (node->PublishStereo(Pair(++*sequence))) ++sent;
    std::this_thread::sleep_for(std::chrono::milliseconds(33));
  }
  return sent;
}

TEST(RobotNodeTest, AFrozenObserverCannotStopTheVideoOfTheOthers) {
  auto robot = MakeParticipant("robot");
  auto viewer = MakeParticipant("operator");
  ASSERT_TRUE(robot && viewer);
  RobotVideoOptions video;
  video.window_pairs = 2;
  video.lane_timeout = std::chrono::milliseconds(300);
  std::string error;
  auto node = RobotNode::Create(robot.get(), {}, &SystemClock::Instance(), &error, video);
  ASSERT_NE(node, nullptr) << error;
  std::atomic<int> viewer_frames{0};
  dds::Reader<ImageType> left(*viewer, dds::topics::kCameraLeft, dds::Stream::kVideo,
                              [&](const auto&) { ++viewer_frames; });
  ASSERT_TRUE(left.ok()) << left.error();

  // The observer that will freeze: a separate process on the same domain.
  const std::string dir = testing::MakeTempDir("mostar_robot_node_");
  testing::Subprocess observer;
  ASSERT_TRUE(observer.Start({std::string(MOSTAR_TEST_BINARY_DIR) + "/tests/network/net_probe",
                              "--domain", std::to_string(dds::PerProcessDomainId()), "--id",
                              "frozen_observer", "--no-ping", "--duration-s", "60"},
                             dir + "/probe.log", &error))
      << error;
  uint64_t sequence = 0;
  for (int i = 0; i < 300 && node->frame_subscribers() < 2; ++i) {
    PublishFor(node.get(), &sequence, std::chrono::milliseconds(33));
  }
  ASSERT_EQ(node->frame_subscribers(), 2) << "the observer process did not match";
  // Both acknowledge: every pair goes out, nothing is reclaimed.
  const int healthy_sent = PublishFor(node.get(), &sequence, std::chrono::milliseconds(2000));
  EXPECT_GE(healthy_sent, 20);  // of 60 (a loaded test machine delays acknowledgements)
  EXPECT_EQ(node->lanes_reclaimed(), 0u);

  observer.Signal(SIGSTOP);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const int frames_before = viewer_frames.load();
  const int frozen_sent = PublishFor(node.get(), &sequence, std::chrono::milliseconds(3000));
  const int frames_during = viewer_frames.load() - frames_before;
  observer.Signal(SIGCONT);
  observer.Signal(SIGTERM);
  observer.Wait(std::chrono::seconds(10));

  // 2 lanes reclaimed every 300 ms: about 20 pairs in 3 s (without reclaiming: none at all).
  EXPECT_GE(frozen_sent, 10) << "the frozen observer held every video lane";
  EXPECT_GE(node->lanes_reclaimed(), 10u);
  EXPECT_GT(node->pairs_skipped(), 0u);
  EXPECT_GE(frames_during, 10) << "the other viewer stopped receiving";
}

// --insecure on a network profile shows in the robot's health; loopback does not.
TEST(RobotNodeTest, HealthSaysWhenDdsSecurityIsOff) {
  const std::string dir = testing::MakeTempDir("mostar_robot_node_");
  const std::string xml = testing::WriteLoopbackUdpProfile(dir, "insecure_robot");
  ASSERT_NE(xml, "");
  dds::ParticipantOptions options;
  options.domain_id = dds::PerProcessDomainId();
  options.profile = xml;
  options.xml_participant_profile = "insecure_robot";
  options.insecure = true;
  std::string error;
  auto insecure = dds::Participant::Create(options, &error);
  ASSERT_NE(insecure, nullptr) << error;
  auto node = RobotNode::Create(insecure.get(), {}, &SystemClock::Instance(), &error);
  ASSERT_NE(node, nullptr) << error;
  const DeviceHealth network = node->NetworkHealth();
  const auto counter = [](const DeviceHealth& health, const std::string& name) {
    for (const auto& [key, value] : health.counters) {
      if (key == name) return value;
    }
    ADD_FAILURE() << "no counter " << name;
    return uint64_t{0};
  };
  EXPECT_EQ(counter(network, "dds_security_off"), 1u);
  EXPECT_EQ(network.state, DeviceState::kWarn);
  EXPECT_NE(network.message.find("dds security off"), std::string::npos) << network.message;
  node.reset();
  insecure.reset();

  auto loopback = MakeParticipant("robot");
  ASSERT_TRUE(loopback);
  node = RobotNode::Create(loopback.get(), {}, &SystemClock::Instance(), &error);
  ASSERT_NE(node, nullptr) << error;
  EXPECT_EQ(counter(node->NetworkHealth(), "dds_security_off"), 0u);
  EXPECT_EQ(node->NetworkHealth().state, DeviceState::kOk);
  EXPECT_EQ(node->NetworkHealth().message.find("dds security off"), std::string::npos);
  node.reset();
  std::remove(xml.c_str());
  ::rmdir(dir.c_str());
}

TEST(RobotNodeTest, RejectsAnInvalidVideoWindow) {
  auto robot = MakeParticipant("robot");
  ASSERT_TRUE(robot);
  std::string error;
  RobotVideoOptions video;
  video.window_pairs = 0;
  EXPECT_EQ(RobotNode::Create(robot.get(), {}, &SystemClock::Instance(), &error, video), nullptr);
  EXPECT_NE(error.find("at least one pair"), std::string::npos) << error;
  video.window_pairs = 1;
  video.lane_timeout = Duration::zero();
  EXPECT_EQ(RobotNode::Create(robot.get(), {}, &SystemClock::Instance(), &error, video), nullptr);
  EXPECT_NE(error.find("lane timeout"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::server
