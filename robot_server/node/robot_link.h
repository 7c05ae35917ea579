// What the robot's control loop needs of its network side: RobotNode implements it on DDS,
// tests implement it in memory. Publish calls never block the caller (RobotNode queues them in
// its outbox), except PublishImage, which the replay's own thread calls; every method is
// thread-safe.
#pragma once

#include <optional>
#include <string>

#include "common/time/time.h"
#include "common/types/bumper.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "common/types/sonar.h"
#include "common/types/stereo_frame.h"

namespace mostar::server {

class RobotLink {
 public:
  RobotLink() = default;
  RobotLink(const RobotLink&) = delete;
  RobotLink& operator=(const RobotLink&) = delete;
  virtual ~RobotLink() = default;

  virtual void PublishScan(const LaserScan& scan) = 0;
  virtual void PublishOdometry(const Odometry& odometry) = 0;
  // One sonar belt cycle: the ring with its mounts, and each sensor on its own (ROS 2 Range).
  virtual void PublishSonar(const SonarRanges& ranges) = 0;
  // The bumper belt's state (the caller publishes it on change and at 1 Hz).
  virtual void PublishBumpers(const BumperState& state) = 0;
  virtual void PublishHealth(const RobotHealth& health) = 0;
  virtual void PublishLease(const ControlLease& lease) = 0;
  virtual void PublishCameraInfo(Eye eye, const CameraIntrinsicsInfo& info) = 0;
  // One eye's image on its own (a replay publishes recorded images one by one).
  virtual void PublishImage(Eye eye, const CompressedImage& image) = 0;
  // Robot clock minus the client's clock, once known.
  virtual std::optional<Duration> RobotMinusClient(const std::string& client_id) const = 0;
  // How long the network write in progress has been blocked at `now`; zero when none is.
  virtual Duration BlockedWriteDuration(SteadyTime now) const = 0;
  // The network side as the health device "network".
  virtual DeviceHealth NetworkHealth() const = 0;
};

}  // namespace mostar::server
