// RobotLink for unit tests: keeps everything published, in order; the clock offset and the
// blocked-write duration are set by the test. Thread-safe.
#pragma once

#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "robot_server/node/robot_link.h"

namespace mostar::server {

class FakeRobotLink final : public RobotLink {
 public:
  void PublishScan(const LaserScan& scan) override {
    Locked([&] { scans.push_back(scan); });
  }
  void PublishOdometry(const Odometry& odometry) override {
    Locked([&] { odometries.push_back(odometry); });
  }
  void PublishSonar(const SonarRanges& ranges) override {
    Locked([&] { sonars.push_back(ranges); });
  }
  void PublishBumpers(const BumperState& state) override {
    Locked([&] { bumpers.push_back(state); });
  }
  void PublishHealth(const RobotHealth& health) override {
    Locked([&] { healths.push_back(health); });
  }
  void PublishLease(const ControlLease& lease) override {
    Locked([&] { leases.push_back(lease); });
  }
  void PublishCameraInfo(Eye eye, const CameraIntrinsicsInfo& info) override {
    Locked([&] { camera_infos.emplace_back(eye, info); });
  }
  void PublishImage(Eye eye, const CompressedImage& image) override {
    Locked([&] { images.emplace_back(eye, image); });
  }
  std::optional<Duration> RobotMinusClient(const std::string&) const override {
    return robot_minus_client;
  }
  Duration BlockedWriteDuration(SteadyTime) const override { return blocked; }
  DeviceHealth NetworkHealth() const override {
    DeviceHealth network;
    network.name = "network";
    return network;
  }

  // Read these after the publishing threads are done.
  std::vector<LaserScan> scans;
  std::vector<Odometry> odometries;
  std::vector<RobotHealth> healths;
  std::vector<SonarRanges> sonars;
  std::vector<BumperState> bumpers;
  std::vector<ControlLease> leases;
  std::vector<std::pair<Eye, CameraIntrinsicsInfo>> camera_infos;
  std::vector<std::pair<Eye, CompressedImage>> images;
  std::optional<Duration> robot_minus_client = Duration::zero();
  Duration blocked{0};

 private:
  template <typename F>
  void Locked(F f) {
    std::lock_guard<std::mutex> lock(mutex_);
    f();
  }
  std::mutex mutex_;
};

}  // namespace mostar::server
