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
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/conversions.h"
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

// Starts a net_probe observer process on this process' domain and publishes pairs until the
// robot's video has `subscribers` matched readers; false with `error` when it does not.
bool StartObserver(const std::string& id, RobotNode* node, int subscribers, uint64_t* sequence,
                   testing::Subprocess* observer, std::string* error) {
  const std::string dir = testing::MakeTempDir("mostar_robot_node_");
  if (!observer->Start({std::string(MOSTAR_TEST_BINARY_DIR) + "/tests/network/net_probe",
                        "--domain", std::to_string(dds::PerProcessDomainId()), "--id", id,
                        "--no-ping", "--duration-s", "60"},
                       dir + "/probe.log", error)) {
    return false;
  }
  for (int i = 0; i < 300 && node->frame_subscribers() < subscribers; ++i) {
    PublishFor(node, sequence, std::chrono::milliseconds(33));
  }
  if (node->frame_subscribers() == subscribers) return true;
  *error = "the observer process did not match";
  return false;
}

TEST(RobotNodeTest, AFrozenObserverCannotStopTheVideoOfTheOthers) {
  auto robot = MakeParticipant("robot");
  auto viewer = MakeParticipant("operator");
  ASSERT_TRUE(robot && viewer);
  RobotVideoOptions video;
  video.window_pairs = 2;
  video.lane_timeout = std::chrono::milliseconds(300);
  std::string error;
  auto node = RobotNode::Create(robot.get(), {}, {}, &SystemClock::Instance(), &error, video);
  ASSERT_NE(node, nullptr) << error;
  std::atomic<int> viewer_frames{0};
  dds::Reader<ImageType> left(*viewer, dds::topics::kCameraLeft, dds::Stream::kVideo,
                              [&](const auto&) { ++viewer_frames; });
  ASSERT_TRUE(left.ok()) << left.error();

  // The observer that will freeze: a separate process on the same domain.
  testing::Subprocess observer;
  uint64_t sequence = 0;
  ASSERT_TRUE(StartObserver("frozen_observer", node.get(), 2, &sequence, &observer, &error))
      << error;
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

// Each pair is acknowledged as soon as it arrives (a heartbeat follows every write), not at
// the next periodic heartbeat: with one lane and a repair period of 3 s, pairs still go out at
// the frame rate to a reader in another process (in-process readers acknowledge at once
// whatever the heartbeats). Before, the lane was freed once per repair period: about 1 pair
// in 2 s.
TEST(RobotNodeTest, TheAckClockRunsOnAcknowledgementsNotOnTheRepairPeriod) {
  auto robot = MakeParticipant("robot");
  ASSERT_TRUE(robot);
  RobotVideoOptions video;
  video.window_pairs = 1;
  video.lane_timeout = std::chrono::seconds(60);  // no reclaiming
  video.repair_period = std::chrono::milliseconds(3000);
  std::string error;
  auto node = RobotNode::Create(robot.get(), {}, {}, &SystemClock::Instance(), &error, video);
  ASSERT_NE(node, nullptr) << error;
  testing::Subprocess observer;
  uint64_t sequence = 0;
  ASSERT_TRUE(StartObserver("observer", node.get(), 1, &sequence, &observer, &error)) << error;
  // Let the pair that was in flight when it matched be acknowledged (at worst by the periodic
  // heartbeat), then count.
  for (int i = 0; i < 400 && !node->PublishStereo(Pair(++sequence)); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const int sent = PublishFor(node.get(), &sequence, std::chrono::milliseconds(2000));
  observer.Signal(SIGTERM);
  observer.Wait(std::chrono::seconds(10));
  EXPECT_GE(sent, 15) << "of about 60: the lane waited for the periodic heartbeat";
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
  auto node = RobotNode::Create(insecure.get(), {}, {}, &SystemClock::Instance(), &error);
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
  node = RobotNode::Create(loopback.get(), {}, {}, &SystemClock::Instance(), &error);
  ASSERT_NE(node, nullptr) << error;
  EXPECT_EQ(counter(node->NetworkHealth(), "dds_security_off"), 0u);
  EXPECT_EQ(node->NetworkHealth().state, DeviceState::kOk);
  EXPECT_EQ(node->NetworkHealth().message.find("dds security off"), std::string::npos);
  node.reset();
  std::remove(xml.c_str());
  ::rmdir(dir.c_str());
}

// A sonar cycle goes out as the ring on rt/mostar/sonar and as one sensor_msgs/Range per
// sensor on rt/mostar/sonar/range; the bumper state is kept for late joiners (transient local).
TEST(RobotNodeTest, PublishesTheSonarRingEachSensorsRangeAndTheBumperState) {
  auto robot = MakeParticipant("robot");
  auto viewer = MakeParticipant("operator");
  ASSERT_TRUE(robot && viewer);
  std::string error;
  auto node = RobotNode::Create(robot.get(), {}, {}, &SystemClock::Instance(), &error);
  ASSERT_NE(node, nullptr) << error;
  BumperState bumpers;
  bumpers.stamp = SystemClock::Instance().Now();
  bumpers.segment_count = 16;
  bumpers.pressed = 1u << 8;
  bumpers.latched = 1u << 8;
  node->PublishBumpers(bumpers);
  ASSERT_TRUE(node->FlushOutbox(std::chrono::seconds(5)));
  // A JPEG robot (VideoOptions::h264 false) has no H.264 writer.
  EXPECT_FALSE(node->PublishStereoVideo(StereoVideoFrame{}));

  std::mutex mutex;
  std::vector<SonarRanges> rings;
  std::set<std::string> range_frames;
  std::optional<BumperState> got_bumpers;
  dds::Reader<mostar_msgs::msg::dds_::SonarRing_PubSubType> ring_reader(
      *viewer, dds::topics::kSonar, dds::Stream::kSensor, [&](const auto& m) {
        std::lock_guard<std::mutex> lock(mutex);
        rings.push_back(dds::FromIdl(m));
      });
  dds::Reader<sensor_msgs::msg::dds_::Range_PubSubType> range_reader(
      *viewer, dds::topics::kSonarRange, dds::Stream::kSensor, [&](const auto& m) {
        std::lock_guard<std::mutex> lock(mutex);
        range_frames.insert(dds::FromIdl(m).mount.frame_id);
      });
  dds::Reader<mostar_msgs::msg::dds_::BumperState_PubSubType> bumper_reader(
      *viewer, dds::topics::kBumpers, dds::Stream::kState, [&](const auto& m) {
        std::lock_guard<std::mutex> lock(mutex);
        got_bumpers = dds::FromIdl(m);
      });
  ASSERT_TRUE(ring_reader.ok() && range_reader.ok() && bumper_reader.ok());
  SonarRanges cycle;
  for (int i = 0; i < 3; ++i) {
    SonarRange r;
    r.mount = SonarMount{"sonar_" + std::to_string(i), 0.1 * i, 0, 0.5 * i};
    r.stamp = SystemClock::Instance().Now();
    r.range_m = 1.0f + static_cast<float>(i);
    r.max_range_m = 6.0f;
    r.field_of_view_rad = 0.96f;
    cycle.ranges.push_back(r);
  }
  // Best effort: publish until both sonar topics arrived (discovery takes a moment).
  bool done = false;
  for (int i = 0; i < 200 && !done; ++i) {  // 10 s at most
    cycle.cycle = static_cast<uint64_t>(i + 1);
    node->PublishSonar(cycle);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::lock_guard<std::mutex> lock(mutex);
    done = !rings.empty() && range_frames.size() == 3 && got_bumpers.has_value();
  }
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_FALSE(rings.empty());
  EXPECT_EQ(rings.back().ranges.size(), 3u);
  EXPECT_FLOAT_EQ(rings.back().ranges[2].range_m, 3.0f);
  EXPECT_EQ(range_frames, (std::set<std::string>{"sonar_0", "sonar_1", "sonar_2"}));
  ASSERT_TRUE(got_bumpers.has_value()) << "the bumper state published before the reader joined";
  EXPECT_EQ(got_bumpers->latched, 1u << 8);
  EXPECT_EQ(got_bumpers->segment_count, 16);
}

// Codec H264: the stereo stream and its Foxglove mirror reach a viewer with the robot's AU
// numbers; a new reader of the stream and a viewer's keyframe request both reach the camera.
TEST(RobotNodeTest, TheH264StreamReachesViewersAndKeyframeRequestsReachTheCamera) {
  auto robot = MakeParticipant("robot");
  auto viewer = MakeParticipant("operator");
  ASSERT_TRUE(robot && viewer);
  std::mutex mutex;
  std::vector<std::string> requests;  // reasons
  RobotNode::Callbacks callbacks;
  callbacks.on_keyframe_request = [&](const KeyframeRequest& request) {
    std::lock_guard<std::mutex> lock(mutex);
    requests.push_back(request.reason);
  };
  std::vector<VideoFeedback> reports;
  callbacks.on_video_feedback = [&](const VideoFeedback& feedback) {
    std::lock_guard<std::mutex> lock(mutex);
    reports.push_back(feedback);
  };
  std::string error;
  RobotNode::VideoOptions video;
  video.h264 = true;
  auto node =
      RobotNode::Create(robot.get(), {}, callbacks, &SystemClock::Instance(), &error, video);
  ASSERT_NE(node, nullptr) << error;
  std::vector<StereoVideoFrame> frames;
  std::vector<std::string> foxglove;  // frame ids
  dds::Reader<mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType> video_reader(
      *viewer, dds::topics::kCameraStereoVideo, dds::VideoStreamReaderQos(dds::kVideoStreamDepth),
      dds::kWithWriter, [&](const auto& m, const dds::WriterId&) {
        std::lock_guard<std::mutex> lock(mutex);
        frames.push_back(dds::FromIdl(m));
      });
  dds::Reader<foxglove_msgs::msg::dds_::CompressedVideo_PubSubType> left_reader(
      *viewer, dds::topics::kCameraLeftVideo, dds::VideoStreamReaderQos(dds::kVideoStreamDepth),
      dds::kWithWriter, [&](const auto& m, const dds::WriterId&) {
        std::lock_guard<std::mutex> lock(mutex);
        foxglove.push_back(m.frame_id() + "/" + m.format());
      });
  dds::Writer<mostar_msgs::msg::dds_::KeyframeRequest_PubSubType> request_writer(
      *viewer, dds::topics::kKeyframeRequest, dds::WriterQos(dds::Stream::kControl));
  ASSERT_TRUE(video_reader.ok() && left_reader.ok() && request_writer.ok());
  auto count = [&](auto& v) {
    std::lock_guard<std::mutex> lock(mutex);
    return v.size();
  };
  for (int i = 0; i < 200 && (node->frame_subscribers() == 0 || count(requests) < 2); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    ASSERT_GE(requests.size(), 2u);  // both readers joined
    EXPECT_EQ(requests[0].substr(0, 4), "join");
  }
  for (int i = 0; i < 200 && request_writer.matched() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(request_writer.Write(
      dds::ToIdl(KeyframeRequest{SystemClock::Instance().Now(), "observer", 7, "gap"})));
  dds::Writer<mostar_msgs::msg::dds_::VideoFeedback_PubSubType> feedback_writer(
      *viewer, dds::topics::kVideoFeedback, dds::WriterQos(dds::Stream::kControl));
  for (int i = 0; i < 200 && feedback_writer.matched() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(feedback_writer.Write(
      dds::ToIdl(VideoFeedback{SystemClock::Instance().Now(), "observer", {{1, 5, 3000}}})));
  for (uint64_t n = 1; n <= 3; ++n) {
    StereoVideoFrame frame;
    frame.sequence = n;
    frame.stamp = SystemClock::Instance().Now();
    frame.idr = n == 1;
    frame.width_px = 640;
    frame.height_px = 480;
    frame.left.assign(2000, static_cast<uint8_t>(n));
    frame.right.assign(1000, static_cast<uint8_t>(n));
    ASSERT_TRUE(node->PublishStereoVideo(frame));
  }
  for (int i = 0; i < 200 && (count(frames) < 3 || count(foxglove) < 3 || count(requests) < 3 ||
                              count(reports) < 1);
       ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(frames.size(), 3u);
  for (uint64_t n = 1; n <= 3; ++n) {
    EXPECT_EQ(frames[n - 1].sequence, n);
    EXPECT_EQ(frames[n - 1].left.size(), 2000u);
    EXPECT_EQ(frames[n - 1].right.front(), n);
  }
  EXPECT_TRUE(frames[0].idr);
  EXPECT_EQ(foxglove, (std::vector<std::string>(3, "camera_left/h264")));
  ASSERT_EQ(requests.size(), 3u);
  EXPECT_EQ(requests[2], "gap");
  EXPECT_EQ(node->keyframe_requests(), 1u);
  EXPECT_EQ(node->video_frames_sent(), 3u);
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].sender_id, "observer");
  ASSERT_EQ(reports[0].arrivals.size(), 1u);
  EXPECT_EQ(reports[0].arrivals[0].bytes, 3000u);
}

TEST(RobotNodeTest, RejectsAnInvalidVideoWindow) {
  auto robot = MakeParticipant("robot");
  ASSERT_TRUE(robot);
  std::string error;
  RobotVideoOptions video;
  video.window_pairs = 0;
  EXPECT_EQ(RobotNode::Create(robot.get(), {}, {}, &SystemClock::Instance(), &error, video),
            nullptr);
  EXPECT_NE(error.find("at least one pair"), std::string::npos) << error;
  video.window_pairs = 1;
  video.lane_timeout = Duration::zero();
  EXPECT_EQ(RobotNode::Create(robot.get(), {}, {}, &SystemClock::Instance(), &error, video),
            nullptr);
  EXPECT_NE(error.find("lane timeout"), std::string::npos) << error;
}

}  // namespace
}  // namespace mostar::server
