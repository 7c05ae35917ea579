// Round trips: plain type -> IDL -> CDR bytes -> IDL -> plain type.
#include "common/dds/conversions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "foxglove_msgsPubSubTypes.h"
#include "mostar_msgsPubSubTypes.h"
#include "ros2_msgsPubSubTypes.h"

namespace mostar::dds {
namespace {

// Serializes with the generated type support, as DDS does on the wire, and back.
template <class PubSubType>
typename PubSubType::type ThroughCdr(const typename PubSubType::type& in) {
  PubSubType type;
  auto copy = in;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(
      static_cast<uint32_t>(type.getSerializedSizeProvider(&copy)()) + 64);
  EXPECT_TRUE(type.serialize(&copy, &payload));
  typename PubSubType::type out;
  EXPECT_TRUE(type.deserialize(&payload, &out));
  return out;
}

const Time kStamp = FromUnixNanos(1'763'769'599'123'456'789);

TEST(ConversionsTest, LaserScanRoundTrip) {
  LaserScan scan;
  scan.stamp = kStamp;
  scan.angle_min_rad = -M_PI / 2;
  scan.angle_increment_rad = M_PI / 180;
  scan.time_increment_s = 1.0f / 75 / 480;
  scan.scan_time_s = 1.0f / 75;
  scan.range_min_m = 0.01f;
  scan.range_max_m = 8.183f;
  for (int i = 0; i < 181; ++i) scan.ranges_m.push_back(0.5f + 0.01f * i);
  scan.ranges_m[7] = std::numeric_limits<float>::quiet_NaN();
  const LaserScan back =
      FromIdl(ThroughCdr<sensor_msgs::msg::dds_::LaserScan_PubSubType>(ToIdl(scan)));
  EXPECT_EQ(back.stamp, scan.stamp);
  EXPECT_FLOAT_EQ(back.angle_min_rad, scan.angle_min_rad);
  EXPECT_FLOAT_EQ(back.angle_increment_rad, scan.angle_increment_rad);
  EXPECT_FLOAT_EQ(back.time_increment_s, scan.time_increment_s);
  EXPECT_FLOAT_EQ(back.scan_time_s, scan.scan_time_s);
  EXPECT_FLOAT_EQ(back.range_max_m, scan.range_max_m);
  ASSERT_EQ(back.ranges_m.size(), 181u);
  EXPECT_TRUE(std::isnan(back.ranges_m[7]));
  EXPECT_FLOAT_EQ(back.ranges_m[180], scan.ranges_m[180]);
  EXPECT_FLOAT_EQ(back.angle_max_rad(), scan.angle_max_rad());
  EXPECT_EQ(ToIdl(scan).header().frame_id(), "laser");
}

TEST(ConversionsTest, CompressedImageRoundTrip) {
  CompressedImage image;
  image.stamp = kStamp;
  image.frame_id = "camera_right";
  image.format = "jpeg";
  image.data = {0xFF, 0xD8, 0x00, 0x11, 0xFF, 0xD9};
  const CompressedImage back =
      FromIdl(ThroughCdr<sensor_msgs::msg::dds_::CompressedImage_PubSubType>(ToIdl(image)));
  EXPECT_EQ(back.stamp, image.stamp);
  EXPECT_EQ(back.frame_id, image.frame_id);
  EXPECT_EQ(back.format, image.format);
  EXPECT_EQ(back.data, image.data);
}

TEST(ConversionsTest, CameraInfoRoundTrip) {
  CameraIntrinsicsInfo info;
  info.stamp = kStamp;
  info.frame_id = "camera_left";
  info.width_px = 640;
  info.height_px = 480;
  info.fx = 440;
  info.fy = 441;
  info.cx = 319.5;
  info.cy = 241;
  info.distortion = {-0.1, 0.02, 0.001, -0.002, 0};
  const wire::CameraInfo w = ToIdl(info);
  EXPECT_EQ(w.distortion_model(), "plumb_bob");
  EXPECT_DOUBLE_EQ(w.p()[0], 440);
  const CameraIntrinsicsInfo back =
      FromIdl(ThroughCdr<sensor_msgs::msg::dds_::CameraInfo_PubSubType>(w));
  EXPECT_EQ(back.stamp, kStamp);
  EXPECT_EQ(back.frame_id, "camera_left");
  EXPECT_EQ(back.width_px, 640);
  EXPECT_EQ(back.height_px, 480);
  EXPECT_DOUBLE_EQ(back.fx, 440);
  EXPECT_DOUBLE_EQ(back.fy, 441);
  EXPECT_DOUBLE_EQ(back.cx, 319.5);
  EXPECT_DOUBLE_EQ(back.cy, 241);
  EXPECT_EQ(back.distortion, info.distortion);
}

TEST(ConversionsTest, OdometryRoundTrip) {
  Odometry odom;
  odom.stamp = kStamp;
  odom.pose = {1.5, -2.25, 3.0};
  odom.linear_mps = 0.4;
  odom.angular_radps = -0.3;
  odom.pose_variance = {0.01, 0.02, 0.003};
  const Odometry back = FromIdl(ThroughCdr<nav_msgs::msg::dds_::Odometry_PubSubType>(ToIdl(odom)));
  EXPECT_EQ(back.stamp, odom.stamp);
  EXPECT_DOUBLE_EQ(back.pose.x_m, 1.5);
  EXPECT_DOUBLE_EQ(back.pose.y_m, -2.25);
  EXPECT_NEAR(back.pose.theta_rad, 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(back.linear_mps, 0.4);
  EXPECT_DOUBLE_EQ(back.angular_radps, -0.3);
  EXPECT_DOUBLE_EQ(back.pose_variance[2], 0.003);
}

TEST(ConversionsTest, OdometryYawWrapsIntoMinusPiPi) {
  Odometry odom;
  odom.pose.theta_rad = -3.1;
  EXPECT_NEAR(FromIdl(ToIdl(odom)).pose.theta_rad, -3.1, 1e-12);
}

TEST(ConversionsTest, VelocityCommandRoundTrip) {
  VelocityCommand cmd{kStamp, 42, "pilot-a", 0.35, -0.7, true};
  const VelocityCommand back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::VelocityCommand_PubSubType>(ToIdl(cmd)));
  EXPECT_EQ(back.stamp, cmd.stamp);
  EXPECT_EQ(back.sequence, 42u);
  EXPECT_EQ(back.sender_id, "pilot-a");
  EXPECT_DOUBLE_EQ(back.linear_mps, 0.35);
  EXPECT_DOUBLE_EQ(back.angular_radps, -0.7);
  EXPECT_TRUE(back.enable);
}

TEST(ConversionsTest, EmergencyStopRoundTrip) {
  EmergencyStop stop{kStamp, "observer-1", true};
  const EmergencyStop back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>(ToIdl(stop)));
  EXPECT_EQ(back.stamp, kStamp);
  EXPECT_EQ(back.sender_id, "observer-1");
  EXPECT_TRUE(back.engage);
}

TEST(ConversionsTest, ControlRequestAndLeaseRoundTrip) {
  ControlRequest req{kStamp, "pilot-b", 20, false};
  const ControlRequest req_back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::ControlRequest_PubSubType>(ToIdl(req)));
  EXPECT_EQ(req_back.sender_id, "pilot-b");
  EXPECT_EQ(req_back.strength, 20);
  EXPECT_FALSE(req_back.take);
  EXPECT_EQ(req_back.stamp, kStamp);

  ControlLease lease{kStamp, "pilot-b", 20, kStamp - std::chrono::seconds(3), 7};
  const ControlLease lease_back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::ControlLease_PubSubType>(ToIdl(lease)));
  EXPECT_EQ(lease_back.holder_id, "pilot-b");
  EXPECT_EQ(lease_back.holder_strength, 20);
  EXPECT_EQ(lease_back.since, lease.since);
  EXPECT_EQ(lease_back.lease_sequence, 7u);
}

TEST(ConversionsTest, RobotHealthRoundTrip) {
  RobotHealth health;
  health.stamp = kStamp;
  health.robot_id = "morduc";
  DeviceHealth laser;
  laser.name = "laser";
  laser.state = DeviceState::kWarn;
  laser.message = "pollution";
  laser.rate_hz = 9.8f;
  laser.counters = {{"crc_errors", 3}, {"resyncs", 1}};
  health.devices.push_back(laser);
  health.lease_holder = "pilot-a";
  health.watchdog_state = WatchdogState::kWaitRearm;
  health.last_command_age_s = 0.12f;
  health.last_command_sequence = 99;
  health.estop_engaged = true;
  const RobotHealth back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::RobotHealth_PubSubType>(ToIdl(health)));
  EXPECT_EQ(back.stamp, kStamp);
  EXPECT_EQ(back.robot_id, "morduc");
  ASSERT_EQ(back.devices.size(), 1u);
  EXPECT_EQ(back.devices[0].name, "laser");
  EXPECT_EQ(back.devices[0].state, DeviceState::kWarn);
  EXPECT_EQ(back.devices[0].message, "pollution");
  EXPECT_FLOAT_EQ(back.devices[0].rate_hz, 9.8f);
  EXPECT_EQ(back.devices[0].counters, laser.counters);
  EXPECT_EQ(back.lease_holder, "pilot-a");
  EXPECT_EQ(back.watchdog_state, WatchdogState::kWaitRearm);
  EXPECT_FLOAT_EQ(back.last_command_age_s, 0.12f);
  EXPECT_EQ(back.last_command_sequence, 99u);
  EXPECT_TRUE(back.estop_engaged);
}

TEST(ConversionsTest, UnknownEnumValuesMapToSafeStates) {
  wire::RobotHealth w;
  w.watchdog_state(200);
  mostar_msgs::msg::dds_::DeviceHealth_ d;
  d.state(77);
  w.devices().push_back(d);
  const RobotHealth back = FromIdl(w);
  EXPECT_EQ(back.watchdog_state, WatchdogState::kEstop);
  EXPECT_EQ(back.devices[0].state, DeviceState::kError);
}

TEST(ConversionsTest, ClockProbeRoundTrip) {
  ClockProbe probe{"pilot-a",
                   5,
                   kStamp,
                   kStamp + std::chrono::milliseconds(30),
                   kStamp + std::chrono::milliseconds(31),
                   kStamp + std::chrono::milliseconds(45)};
  const ClockProbe back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::ClockProbe_PubSubType>(ToIdl(probe)));
  EXPECT_EQ(back.sender_id, "pilot-a");
  EXPECT_EQ(back.sequence, 5u);
  EXPECT_EQ(back.t0, probe.t0);
  EXPECT_EQ(back.t1, probe.t1);
  EXPECT_EQ(back.t2, probe.t2);
  EXPECT_EQ(back.t3, probe.t3);
}

// Bounded strings and sequences (idl/mostar_msgs.idl): longer values are cut, never sent
// beyond their bound.
TEST(ConversionsTest, StringsAndSequencesAreCutAtTheirBounds) {
  VelocityCommand cmd;
  cmd.sender_id = std::string(100, 'a');
  const VelocityCommand cut =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::VelocityCommand_PubSubType>(ToIdl(cmd)));
  EXPECT_EQ(cut.sender_id, std::string(64, 'a'));
  ClockProbe probe;
  probe.sender_id = std::string("alice\0mallory", 13);
  EXPECT_EQ(FromIdl(ToIdl(probe)).sender_id, "alice");  // never a longer id than written

  RobotHealth health;
  health.robot_id = std::string(80, 'r');
  for (int d = 0; d < 20; ++d) {
    DeviceHealth device;
    device.name = "device" + std::to_string(d);
    device.message = std::string(300, 'm');
    for (int c = 0; c < 70; ++c) device.counters.emplace_back("c" + std::to_string(c), c);
    health.devices.push_back(device);
  }
  const RobotHealth back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::RobotHealth_PubSubType>(ToIdl(health)));
  EXPECT_EQ(back.robot_id.size(), 64u);
  ASSERT_EQ(back.devices.size(), kMaxHealthDevices);
  EXPECT_EQ(back.devices[15].name, "device15");
  EXPECT_EQ(back.devices[0].message.size(), 256u);
  ASSERT_EQ(back.devices[0].counters.size(), kMaxHealthCounters);
  EXPECT_EQ(back.devices[0].counters.back().first, "c63");
}

// The robot's readers of these types use preallocated samples of the type's maximum size
// (common/dds/qos.cc), which refuses anything bigger: the maximum must be small.
TEST(ConversionsTest, CommandTypesHaveASmallMaximumSize) {
  EXPECT_LE(mostar_msgs::msg::dds_::VelocityCommand_PubSubType().m_typeSize, 200u);
  EXPECT_LE(mostar_msgs::msg::dds_::EmergencyStop_PubSubType().m_typeSize, 200u);
  EXPECT_LE(mostar_msgs::msg::dds_::ControlRequest_PubSubType().m_typeSize, 200u);
  EXPECT_LE(mostar_msgs::msg::dds_::ClockProbe_PubSubType().m_typeSize, 200u);
  EXPECT_LE(mostar_msgs::msg::dds_::ControlLease_PubSubType().m_typeSize, 200u);
  EXPECT_LE(mostar_msgs::msg::dds_::BumperState_PubSubType().m_typeSize, 200u);
  // Health: 16 devices of 64 counters each.
  EXPECT_LE(mostar_msgs::msg::dds_::RobotHealth_PubSubType().m_typeSize, 16u * 64u * 96u);
}

TEST(ConversionsTest, RosTypeNamesAreExact) {
  EXPECT_EQ(std::string(sensor_msgs::msg::dds_::LaserScan_PubSubType().getName()),
            "sensor_msgs::msg::dds_::LaserScan_");
  EXPECT_EQ(std::string(sensor_msgs::msg::dds_::CompressedImage_PubSubType().getName()),
            "sensor_msgs::msg::dds_::CompressedImage_");
  EXPECT_EQ(std::string(nav_msgs::msg::dds_::Odometry_PubSubType().getName()),
            "nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(std::string(sensor_msgs::msg::dds_::Range_PubSubType().getName()),
            "sensor_msgs::msg::dds_::Range_");
}

SonarRange MakeSonar(int i, float range_m) {
  SonarRange r;
  r.mount.frame_id = "sonar_" + std::to_string(i);
  r.mount.x_m = 0.25 * std::cos(i * M_PI / 4);
  r.mount.y_m = 0.25 * std::sin(i * M_PI / 4);
  r.mount.yaw_rad = i * M_PI / 4;
  r.stamp = kStamp + std::chrono::milliseconds(65 * i);
  r.range_m = range_m;
  r.min_range_m = 0.03f;
  r.max_range_m = 6.0f;
  r.field_of_view_rad = 0.96f;
  return r;
}

TEST(ConversionsTest, SonarRingRoundTripKeepsMountsAndSpecialRanges) {
  SonarRanges ring;
  ring.cycle = 42;
  ring.ranges = {MakeSonar(0, 1.25f), MakeSonar(1, std::numeric_limits<float>::infinity()),
                 MakeSonar(2, std::numeric_limits<float>::quiet_NaN())};
  const wire::SonarRing w = ThroughCdr<mostar_msgs::msg::dds_::SonarRing_PubSubType>(ToIdl(ring));
  EXPECT_EQ(FromIdl(w.stamp()), ring.ranges[2].stamp);  // the newest sensor stamp
  const SonarRanges back = FromIdl(w);
  EXPECT_EQ(back.cycle, 42u);
  ASSERT_EQ(back.ranges.size(), 3u);
  EXPECT_EQ(back.ranges[1].mount.frame_id, "sonar_1");
  EXPECT_NEAR(back.ranges[1].mount.x_m, ring.ranges[1].mount.x_m, 1e-6);
  EXPECT_NEAR(back.ranges[1].mount.y_m, ring.ranges[1].mount.y_m, 1e-6);
  EXPECT_NEAR(back.ranges[1].mount.yaw_rad, M_PI / 4, 1e-6);
  EXPECT_EQ(back.ranges[1].stamp, ring.ranges[1].stamp);
  EXPECT_FLOAT_EQ(back.ranges[0].range_m, 1.25f);
  EXPECT_TRUE(std::isinf(back.ranges[1].range_m));
  EXPECT_TRUE(std::isnan(back.ranges[2].range_m));
  EXPECT_FLOAT_EQ(back.ranges[0].min_range_m, 0.03f);
  EXPECT_FLOAT_EQ(back.ranges[0].max_range_m, 6.0f);
  EXPECT_FLOAT_EQ(back.ranges[0].field_of_view_rad, 0.96f);
}

TEST(ConversionsTest, SonarRingKeepsAtMostItsBound) {
  SonarRanges ring;
  for (int i = 0; i < 40; ++i) ring.ranges.push_back(MakeSonar(i, 1.0f));
  const SonarRanges back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::SonarRing_PubSubType>(ToIdl(ring)));
  ASSERT_EQ(back.ranges.size(), kMaxSonars);
  EXPECT_EQ(back.ranges.back().mount.frame_id, "sonar_31");
}

TEST(ConversionsTest, SonarAsRosRangeIsUltrasoundInItsOwnFrame) {
  const SonarRange sonar = MakeSonar(5, 2.5f);
  const wire::Range w = ThroughCdr<sensor_msgs::msg::dds_::Range_PubSubType>(ToIdl(sonar));
  EXPECT_EQ(w.radiation_type(), 0);
  EXPECT_EQ(w.header().frame_id(), "sonar_5");
  EXPECT_EQ(w.variance(), 0.0f);
  const SonarRange back = FromIdl(w);
  EXPECT_EQ(back.mount.frame_id, "sonar_5");
  EXPECT_EQ(back.stamp, sonar.stamp);
  EXPECT_FLOAT_EQ(back.range_m, 2.5f);
  EXPECT_FLOAT_EQ(back.min_range_m, 0.03f);
  EXPECT_FLOAT_EQ(back.max_range_m, 6.0f);
  EXPECT_FLOAT_EQ(back.field_of_view_rad, 0.96f);
}

TEST(ConversionsTest, FrameTimingRoundTrip) {
  const FrameTiming timing{kStamp, kStamp + std::chrono::microseconds(1500),
                           kStamp + std::chrono::microseconds(2100)};
  const FrameTiming back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::FrameTiming_PubSubType>(ToIdl(timing)));
  EXPECT_EQ(back.capture, timing.capture);
  EXPECT_EQ(back.encoded, timing.encoded);
  EXPECT_EQ(back.written, timing.written);
}

TEST(ConversionsTest, StereoVideoFrameRoundTrip) {
  StereoVideoFrame frame;
  frame.sequence = 41;
  frame.stamp = kStamp;
  frame.encoded = kStamp + std::chrono::microseconds(3200);
  frame.idr = true;
  frame.width_px = 1280;
  frame.height_px = 960;
  frame.left = {0, 0, 0, 1, 0x67, 0x42};
  frame.right = {0, 0, 1, 0x65};
  const StereoVideoFrame back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType>(ToIdl(frame)));
  EXPECT_EQ(back.sequence, 41u);
  EXPECT_EQ(back.stamp, frame.stamp);
  EXPECT_EQ(back.encoded, frame.encoded);
  EXPECT_TRUE(back.idr);
  EXPECT_EQ(back.width_px, 1280);
  EXPECT_EQ(back.height_px, 960);
  EXPECT_EQ(back.format, "h264");
  EXPECT_EQ(back.left, frame.left);
  EXPECT_EQ(back.right, frame.right);
  frame.width_px = 70000;  // clamped, not wrapped
  EXPECT_EQ(ToIdl(frame).width_px(), 65535);
}

TEST(ConversionsTest, KeyframeRequestRoundTripCutsLongStrings) {
  const KeyframeRequest request{kStamp, std::string(80, 'a'), 17, "gap"};
  const KeyframeRequest back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::KeyframeRequest_PubSubType>(ToIdl(request)));
  EXPECT_EQ(back.stamp, kStamp);
  EXPECT_EQ(back.sender_id, std::string(64, 'a'));
  EXPECT_EQ(back.last_sequence, 17u);
  EXPECT_EQ(back.reason, "gap");
}

TEST(ConversionsTest, VideoFeedbackRoundTripKeepsAtMostItsBound) {
  VideoFeedback feedback;
  feedback.stamp = kStamp;
  feedback.sender_id = "alice";
  for (uint64_t n = 1; n <= 70; ++n) {
    feedback.arrivals.push_back({n, static_cast<int64_t>(n) * 33'000'000 - 5, 1000 + uint32_t(n)});
  }
  const VideoFeedback back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::VideoFeedback_PubSubType>(ToIdl(feedback)));
  EXPECT_EQ(back.stamp, kStamp);
  EXPECT_EQ(back.sender_id, "alice");
  ASSERT_EQ(back.arrivals.size(), VideoFeedback::kMaxArrivals);
  EXPECT_EQ(back.arrivals[9].sequence, 10u);
  EXPECT_EQ(back.arrivals[9].arrival_ns, 330'000'000 - 5);
  EXPECT_EQ(back.arrivals[9].bytes, 1010u);
}

TEST(ConversionsTest, FoxgloveVideoCarriesOneEye) {
  StereoVideoFrame frame;
  frame.stamp = kStamp;
  frame.left = {1, 2};
  frame.right = {3};
  const auto left = ThroughCdr<foxglove_msgs::msg::dds_::CompressedVideo_PubSubType>(
      ToFoxgloveVideo(frame, Eye::kLeft));
  EXPECT_EQ(FromIdl(left.timestamp()), kStamp);
  EXPECT_EQ(left.frame_id(), "camera_left");
  EXPECT_EQ(left.format(), "h264");
  EXPECT_EQ(left.data(), frame.left);
  EXPECT_EQ(ToFoxgloveVideo(frame, Eye::kRight).data(), frame.right);
  EXPECT_EQ(ToFoxgloveVideo(frame, Eye::kRight).frame_id(), "camera_right");
}

TEST(ConversionsTest, BumperStateRoundTripAndClampedSegmentCount) {
  BumperState state;
  state.stamp = kStamp;
  state.segment_count = 16;
  state.pressed = 0x8001u;
  state.latched = 0x0001u;
  state.readable = false;
  BumperState back =
      FromIdl(ThroughCdr<mostar_msgs::msg::dds_::BumperState_PubSubType>(ToIdl(state)));
  EXPECT_EQ(back.stamp, kStamp);
  EXPECT_EQ(back.segment_count, 16);
  EXPECT_EQ(back.pressed, 0x8001u);
  EXPECT_EQ(back.latched, 0x0001u);
  EXPECT_FALSE(back.readable);

  wire::BumperState too_many = ToIdl(state);
  too_many.segment_count(200);
  back = FromIdl(too_many);
  EXPECT_EQ(back.segment_count, kMaxBumperSegments);
  state.segment_count = 99;
  EXPECT_EQ(ToIdl(state).segment_count(), kMaxBumperSegments);
}

}  // namespace
}  // namespace mostar::dds
