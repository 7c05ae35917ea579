// The robot's DDS face: publishes sensors, state and health, receives commands.
//
// Knows DDS and the wire types; knows nothing of devices. Callbacks run on DDS threads and must
// be quick (hand the data over, do not block). Clock pings are answered here (NTP-style pong
// with receive and send stamps on the robot clock).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "common/dds/endpoint.h"
#include "common/time/time.h"
#include "common/timesync/clock_offset_estimator.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "common/types/stereo_frame.h"
#include "mostar_msgsPubSubTypes.h"
#include "ros2_msgsPubSubTypes.h"

namespace mostar::server {

class RobotNode {
 public:
  struct Callbacks {
    std::function<void(const VelocityCommand&)> on_command;
    std::function<void(const EmergencyStop&)> on_estop;
    std::function<void(const ControlRequest&)> on_control_request;
    // Number of live command writers changed (a pilot appeared or vanished).
    std::function<void(int alive_writers)> on_command_writers;
  };

  // Creates every endpoint; null with `error` when one cannot be created.
  static std::unique_ptr<RobotNode> Create(dds::Participant* participant, Callbacks callbacks,
                                           const Clock* clock, std::string* error);

  // Both eyes; false when the pair was not sent: skipped at the source because readers have not
  // acknowledged the previous one yet (ack-clock), or refused by DDS.
  bool PublishStereo(const CompressedStereoPair& pair);
  // Intrinsics of one eye (transient local: late joiners get them at once).
  void PublishCameraInfo(Eye eye, const CameraIntrinsicsInfo& info);
  // One eye, unconditionally (replay).
  void PublishImage(Eye eye, const CompressedImage& image);
  void PublishScan(const LaserScan& scan);
  void PublishOdometry(const Odometry& odometry);
  void PublishHealth(const RobotHealth& health);
  void PublishLease(const ControlLease& lease);

  // Robot clock minus the client's clock, once enough ping exchanges completed.
  std::optional<Duration> RobotMinusClient(const std::string& client_id) const;

  // Remote endpoints currently matched (for health: how many viewers and pilots).
  int frame_subscribers() const { return left_->matched(); }
  int command_writers() const { return command_->matched(); }

 private:
  RobotNode() = default;

  void OnPing(const ClockProbe& ping);

  const Clock* clock_ = nullptr;
  Callbacks callbacks_;
  timesync::ClockOffsetTable clock_offsets_;
  std::mutex pong_mutex_;
  std::map<std::string, ClockProbe> last_pong_;  // per client: the pong we sent last
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::CompressedImage_PubSubType>> left_;
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::CompressedImage_PubSubType>> right_;
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::CameraInfo_PubSubType>> left_info_;
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::CameraInfo_PubSubType>> right_info_;
  std::unique_ptr<dds::Writer<sensor_msgs::msg::dds_::LaserScan_PubSubType>> scan_;
  std::unique_ptr<dds::Writer<nav_msgs::msg::dds_::Odometry_PubSubType>> odom_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::RobotHealth_PubSubType>> health_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ControlLease_PubSubType>> lease_;
  std::unique_ptr<dds::Writer<mostar_msgs::msg::dds_::ClockProbe_PubSubType>> pong_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::VelocityCommand_PubSubType>> command_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::EmergencyStop_PubSubType>> estop_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::ControlRequest_PubSubType>> request_;
  std::unique_ptr<dds::Reader<mostar_msgs::msg::dds_::ClockProbe_PubSubType>> ping_;
};

}  // namespace mostar::server
