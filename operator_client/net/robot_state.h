// What the operator knows about the robot besides video: recent scans (to match each image with
// the scan nearest in time), recent odometry (to move a scan to an image's time), the latest
// health, lease, odometry, sonar cycle and bumper state, and the clock offset to the robot.
// Written from DDS threads, read by the render loop. Thread-safe.
#pragma once

#include <deque>
#include <mutex>
#include <optional>

#include "common/time/rate_meter.h"
#include "common/timesync/clock_offset_estimator.h"
#include "common/types/bumper.h"
#include "common/types/commands.h"
#include "common/types/health.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "common/types/sonar.h"
#include "common/types/stereo_frame.h"
#include "operator_client/fusion/motion_compensation.h"

namespace mostar::client {

struct RobotSnapshot {
  std::optional<RobotHealth> health;
  std::optional<ControlLease> lease;
  std::optional<Odometry> odometry;  // the newest by stamp
  std::optional<LaserScan> latest_scan;
  std::optional<SonarRanges> sonar;                     // the latest belt cycle
  std::optional<BumperState> bumpers;                   // the latest bumper state
  std::optional<CameraIntrinsicsInfo> left_intrinsics;  // published by the robot
  std::optional<CameraIntrinsicsInfo> right_intrinsics;
  timesync::ClockOffsetEstimate clock;  // robot clock minus this machine's clock
  double scan_rate_hz = 0;
  uint64_t scans = 0;
  SteadyTime last_scan_received;
  SteadyTime last_health_received;
  SteadyTime last_odometry_received;
  SteadyTime last_sonar_received;
  SteadyTime last_bumpers_received;
  // Clock pings lost on the control path: the share of the last kPingLossWindow ping sequence
  // numbers (up to the newest pong) whose pong never came; -1 until two pongs arrived.
  double ping_loss = -1;
};

class RobotState {
 public:
  explicit RobotState(const Clock* clock) : clock_(clock) {}

  void AddScan(const LaserScan& scan);
  void SetHealth(const RobotHealth& health);
  void SetLease(const ControlLease& lease);
  void SetOdometry(const Odometry& odometry);
  void SetSonar(const SonarRanges& sonar);
  void SetBumpers(const BumperState& bumpers);
  // The robot-side stages of a pair; the last kTimingHistory are kept.
  void AddFrameTiming(const FrameTiming& timing);
  static constexpr size_t kTimingHistory = 64;
  // The robot-side stages of the pair captured at `capture` (robot clock), when known.
  std::optional<FrameTiming> TimingOf(Time capture) const;
  void SetIntrinsics(Eye eye, const CameraIntrinsicsInfo& info);
  // A pong for one of our pings; t3 is taken now.
  void AddClockSample(const ClockProbe& probe);

  // When the pong to ping `sequence` came back (epoch when it did not), for the next ping's t3.
  Time PongReceipt(uint64_t sequence) const;

  // The scan whose stamp is nearest to `stamp` (robot clock), among those stamped within
  // kScanHistory of the newest (at most kMaxScans: 3.4 s at the LMS200's 75 Hz).
  std::optional<LaserScan> NearestScan(Time stamp) const;
  // `scan`'s beams in the base frame at `image_stamp` (robot clock), moved with the odometry
  // received (the last kOdometryHistory samples; fusion::MoveScanToImageTime).
  void MoveScanToImageTime(const LaserScan& scan, Time image_stamp,
                           const fusion::MotionCompensationOptions& options,
                           fusion::MovedScan* out) const;
  static constexpr size_t kOdometryHistory = 256;  // 5 s at the robot's 50 Hz
  RobotSnapshot Snapshot() const;
  // The e-stop state of the latest health (nullopt before the first), and in `received` when
  // that health arrived here. Cheaper than Snapshot(), for the command thread.
  std::optional<bool> EstopEngaged(SteadyTime* received) const;

 private:
  const Clock* clock_;
  mutable std::mutex mutex_;
  std::deque<LaserScan> scans_;
  std::deque<FrameTiming> timings_;
  fusion::OdometryHistory odometry_{kOdometryHistory};
  mutable RateMeter scan_rate_;
  timesync::ClockOffsetEstimator offset_;
  RobotSnapshot snapshot_;
  static constexpr size_t kPingLossWindow = 50;
  static constexpr Duration kScanHistory = std::chrono::seconds(3);
  static constexpr size_t kMaxScans = 256;
  std::deque<uint64_t> pong_sequences_;  // received, increasing, at most kPingLossWindow
  uint64_t last_pong_sequence_ = 0;
  Time last_pong_receipt_;
};

}  // namespace mostar::client
