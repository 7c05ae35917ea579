// Conversions between mostar's plain types (common/types/) and the DDS wire types (idl/).
// The only place where both meet. Each pair has a round-trip test.
//
// mostar_msgs strings and sequences are bounded (idl/mostar_msgs.idl): ToIdl cuts longer
// strings at their bound (and at an embedded NUL), and keeps the first kMaxHealthDevices
// devices and the first kMaxHealthCounters counters of each; ids longer than 64 bytes are
// never valid client ids (common/identity/client_id.h), so a cut id is refused by the robot.
#pragma once

#include "common/time/time.h"
#include "common/types/bumper.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "common/types/sonar.h"
#include "common/types/stereo_frame.h"
#include "foxglove_msgs.h"
#include "mostar_msgs.h"
#include "ros2_msgs.h"

namespace mostar::dds {

namespace wire {
using Time = builtin_interfaces::msg::dds_::Time_;
using LaserScan = sensor_msgs::msg::dds_::LaserScan_;
using CompressedImage = sensor_msgs::msg::dds_::CompressedImage_;
using CameraInfo = sensor_msgs::msg::dds_::CameraInfo_;
using Odometry = nav_msgs::msg::dds_::Odometry_;
using VelocityCommand = mostar_msgs::msg::dds_::VelocityCommand_;
using EmergencyStop = mostar_msgs::msg::dds_::EmergencyStop_;
using ControlRequest = mostar_msgs::msg::dds_::ControlRequest_;
using ControlLease = mostar_msgs::msg::dds_::ControlLease_;
using RobotHealth = mostar_msgs::msg::dds_::RobotHealth_;
using ClockProbe = mostar_msgs::msg::dds_::ClockProbe_;
using Range = sensor_msgs::msg::dds_::Range_;
using FrameTiming = mostar_msgs::msg::dds_::FrameTiming_;
using SonarRing = mostar_msgs::msg::dds_::SonarRing_;
using BumperState = mostar_msgs::msg::dds_::BumperState_;
using StereoVideoFrame = mostar_msgs::msg::dds_::StereoVideoFrame_;
using KeyframeRequest = mostar_msgs::msg::dds_::KeyframeRequest_;
using VideoFeedback = mostar_msgs::msg::dds_::VideoFeedback_;
using CompressedVideo = foxglove_msgs::msg::dds_::CompressedVideo_;
}  // namespace wire

// Bounds of RobotHealth_ (idl/mostar_msgs.idl).
inline constexpr size_t kMaxHealthDevices = 16;
inline constexpr size_t kMaxHealthCounters = 64;
// Bounds of SonarRing_ and BumperState_.
inline constexpr size_t kMaxSonars = 32;
inline constexpr int kMaxBumperSegments = 32;

// Frame ids used in headers.
inline constexpr const char* kLaserFrame = "laser";
inline constexpr const char* kOdomFrame = "odom";
inline constexpr const char* kBaseFrame = "base_link";

wire::Time ToIdl(Time t);
Time FromIdl(const wire::Time& t);

// The scan sequence number is not part of the ROS layout; FromIdl leaves it 0.
wire::LaserScan ToIdl(const LaserScan& scan);
LaserScan FromIdl(const wire::LaserScan& scan);

wire::CompressedImage ToIdl(const CompressedImage& image);
CompressedImage FromIdl(const wire::CompressedImage& image);

// Planar odometry as nav_msgs/Odometry: yaw as a quaternion about z; pose covariance diagonal
// (x, y, yaw), unknown z/roll/pitch marked with a large variance.
wire::CameraInfo ToIdl(const CameraIntrinsicsInfo& info);
CameraIntrinsicsInfo FromIdl(const wire::CameraInfo& info);

wire::Odometry ToIdl(const Odometry& odom);
Odometry FromIdl(const wire::Odometry& odom);

wire::VelocityCommand ToIdl(const VelocityCommand& cmd);
VelocityCommand FromIdl(const wire::VelocityCommand& cmd);

wire::EmergencyStop ToIdl(const EmergencyStop& stop);
EmergencyStop FromIdl(const wire::EmergencyStop& stop);

wire::ControlRequest ToIdl(const ControlRequest& request);
ControlRequest FromIdl(const wire::ControlRequest& request);

wire::ControlLease ToIdl(const ControlLease& lease);
ControlLease FromIdl(const wire::ControlLease& lease);

wire::RobotHealth ToIdl(const RobotHealth& health);
RobotHealth FromIdl(const wire::RobotHealth& health);

wire::ClockProbe ToIdl(const ClockProbe& probe);
ClockProbe FromIdl(const wire::ClockProbe& probe);

wire::FrameTiming ToIdl(const FrameTiming& timing);
FrameTiming FromIdl(const wire::FrameTiming& timing);

// Width and height are clamped to 0..65535; strings cut at their bounds.
wire::StereoVideoFrame ToIdl(const StereoVideoFrame& frame);
StereoVideoFrame FromIdl(const wire::StereoVideoFrame& frame);

wire::KeyframeRequest ToIdl(const KeyframeRequest& request);
KeyframeRequest FromIdl(const wire::KeyframeRequest& request);

// Keeps the first VideoFeedback::kMaxArrivals arrivals.
wire::VideoFeedback ToIdl(const VideoFeedback& feedback);
VideoFeedback FromIdl(const wire::VideoFeedback& feedback);

// One eye of `frame` as foxglove_msgs/CompressedVideo (frame_id "camera_left" or
// "camera_right", format "h264", the capture stamp).
wire::CompressedVideo ToFoxgloveVideo(const StereoVideoFrame& frame, Eye eye);

// The belt's cycle with every sensor's mount; the ring's stamp is the newest sensor stamp.
// Keeps the first kMaxSonars sensors; frame ids longer than 32 bytes are cut.
wire::SonarRing ToIdl(const SonarRanges& ranges);
SonarRanges FromIdl(const wire::SonarRing& ring);

// One sensor as ROS 2 sensor_msgs/Range (ULTRASOUND, frame_id = the sensor's frame, variance 0
// = unknown). The mount is not part of the ROS layout: FromIdl leaves it at the origin.
wire::Range ToIdl(const SonarRange& range);
SonarRange FromIdl(const wire::Range& range);

// FromIdl clamps segment_count to kMaxBumperSegments.
wire::BumperState ToIdl(const BumperState& state);
BumperState FromIdl(const wire::BumperState& state);

}  // namespace mostar::dds
