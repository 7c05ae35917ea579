// The operator's DDS face: receives the robot's frames, scans, odometry, sonar ring, bumper
// state, health and lease; sends velocity commands, emergency stops, control requests and clock
// pings.
//
// Knows DDS and the wire types; knows nothing of OpenGL. Callbacks run on DDS threads and must
// hand data over quickly. Command ownership is shared: the robot hears every pilot and drives
// with the lease holder's commands only.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "common/dds/endpoint.h"
#include "common/types/bumper.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "common/types/sonar.h"
#include "common/types/stereo_frame.h"
#include "mostar_msgsPubSubTypes.h"
#include "ros2_msgsPubSubTypes.h"

namespace mostar::client {

class OperatorNode {
 public:
  struct Callbacks {
    std::function<void(Eye, const CompressedImage&)> on_image;
    std::function<void(const LaserScan&)> on_scan;
    std::function<void(const Odometry&)> on_odometry;
    std::function<void(const RobotHealth&)> on_health;
    std::function<void(const ControlLease&)> on_lease;
    std::function<void(const ClockProbe&)> on_pong;
    std::function<void(Eye, const CameraIntrinsicsInfo&)> on_camera_info;
    std::function<void(const SonarRanges&)> on_sonar;
    std::function<void(const BumperState&)> on_bumpers;
    std::function<void(const FrameTiming&)> on_frame_timing;
    // Both eyes as H.264 access units (the robot's camera codec H264).
    std::function<void(const StereoVideoFrame&)> on_video;
  };
  struct Options {
    // This console's client id (valid: client_id.h); its commands, e-stops, control requests and
    // clock pings are written in its partition (common/identity/sender_partition.h).
    std::string client_id = "operator";
    bool pilot = false;  // observers create no command writer
    // Which endpoints this node has. A pilot that takes its video through mostar_relay (one
    // copy up the robot's uplink) runs two nodes: kAllButVideo on the robot's domain and
    // kVideoOnly (camera images, frame timing, the H.264 stream, keyframe requests, receive
    // reports) on the relay's observer domain.
    enum class Streams { kAll, kAllButVideo, kVideoOnly };
    Streams streams = Streams::kAll;
  };

  static std::unique_ptr<OperatorNode> Create(dds::Participant* participant, const Options& options,
                                              Callbacks callbacks, std::string* error);

  // False for observers, for a node without the writer (Options::streams) and when DDS refused
  // the sample.
  bool SendCommand(const VelocityCommand& command);
  bool SendEmergencyStop(const EmergencyStop& stop);
  bool SendControlRequest(const ControlRequest& request);
  bool SendPing(const ClockProbe& probe);
  // Asks the robot for an IDR; false when DDS refused it or the permissions did not allow the
  // writer (signed before the topic existed: a warning was logged at creation).
  bool SendKeyframeRequest(const KeyframeRequest& request);
  // A receive report for the robot's rate control; false as SendKeyframeRequest.
  bool SendVideoFeedback(const VideoFeedback& feedback);

  bool robot_seen() const {
    return (scan_ && scan_->matched() > 0) || (health_ && health_->matched() > 0) ||
           (video_ && video_->matched() > 0);
  }
  bool is_pilot() const { return command_ != nullptr; }

 private:
  OperatorNode() = default;
  Callbacks callbacks_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::CompressedImage_PubSubType>> left_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::CompressedImage_PubSubType>> right_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::CameraInfo_PubSubType>> left_info_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::CameraInfo_PubSubType>> right_info_;
  std::unique_ptr<dds::Reader<sensor_msgs::msg::dds_::LaserScan_PubSubType>> scan_;
  std::unique_ptr<dds::Reader<nav_msgs::msg::dds_::Odometry_PubSubType>> odom_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::RobotHealth_PubSubType>> health_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::ControlLease_PubSubType>> lease_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::ClockProbe_PubSubType>> pong_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::SonarRing_PubSubType>> sonar_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::BumperState_PubSubType>> bumpers_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::FrameTiming_PubSubType>> timing_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::StereoVideoFrame_PubSubType>> video_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::KeyframeRequest_PubSubType>> keyframe_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::VideoFeedback_PubSubType>> feedback_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::VelocityCommand_PubSubType>> command_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>> estop_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ControlRequest_PubSubType>> request_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ClockProbe_PubSubType>> ping_;
};

}  // namespace mostar::client
