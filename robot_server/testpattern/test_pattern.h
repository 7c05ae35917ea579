// Built-in test sources for running robot_server with no hardware and no simulator scene:
// a kinematic robot in a rectangular room, a stereo test-pattern camera and a synthetic scan
// of the room. Deterministic and cheap; the simulator (robot_server/sim) is the realistic one.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "common/time/time.h"
#include "common/types/laser_scan.h"
#include "common/types/odometry.h"
#include "robot_server/camera/stereo_camera.h"
#include "robot_server/drive/drive_motors.h"
#include "robot_server/laser/laser_scanner.h"

namespace mostar::testpattern {

struct RoomOptions {
  double half_length_m = 4.0;  // room spans x in [-half_length, half_length] (odom frame)
  double half_width_m = 2.5;   // and y in [-half_width, half_width]
  double wheel_radius_m = 0.1;
  double track_width_m = 0.5;
  int ticks_per_turn = 500;
};

// A unicycle that integrates commanded velocities on the clock; implements DriveMotors so that
// the server's control path is the same as with real motors. Thread-safe.
class KinematicRobot final : public drive::DriveMotors {
 public:
  KinematicRobot(const RoomOptions& options, const Clock* clock);

  bool SetWheelVelocities(const drive::WheelVelocities& wheels, std::string* error) override;
  bool SetVelocity(double linear_mps, double angular_radps, std::string* error) override;
  bool Stop(std::string* error, bool clear_faults = false) override;
  drive::MotorStatus Status() const override;
  bool ReadEncoders(drive::EncoderReading* reading, std::string* error) override;
  int counter_bits() const override { return 16; }

  Pose2D TruePose() const;
  const RoomOptions& options() const { return options_; }

 private:
  void AdvanceLocked();

  const RoomOptions options_;
  const Clock* clock_;
  mutable std::mutex mutex_;
  SteadyTime last_;
  Pose2D pose_;
  double linear_mps_ = 0;
  double angular_radps_ = 0;
  double left_ticks_ = 0;
  double right_ticks_ = 0;
};

// 181 beams over 180 degrees, ranges to the room walls from the robot's true pose.
LaserScan SyntheticScan(const KinematicRobot& robot, Time stamp, uint64_t sequence);

// SyntheticScan as a laser device: `rate_hz` scans per second on its own thread, stamped with
// the clock's wall time, sequence numbers from 1. Health "laser" is kOk while running.
class TestPatternLaser final : public laser::LaserScanner {
 public:
  // `robot` outlives this; `rate_hz` > 0.
  TestPatternLaser(const KinematicRobot* robot, double rate_hz, const Clock* clock);
  ~TestPatternLaser() override;
  bool Start(ScanCallback on_scan, std::string* error) override;
  void Stop() override;
  DeviceHealth Health() const override;

 private:
  void Run(ScanCallback on_scan);

  const KinematicRobot* robot_;
  const double rate_hz_;
  const Clock* clock_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
  std::atomic<uint64_t> scans_{0};
};

// Renders a stereo pair: a floor grid seen from a tilted camera, the time and the robot pose.
class TestPatternCamera final : public camera::StereoCamera {
 public:
  TestPatternCamera(const KinematicRobot* robot, int width, int height, double rate_hz,
                    const Clock* clock);
  bool Open(std::string* error) override;
  camera::GrabResult Grab(Duration timeout, camera::StereoImagePair* pair) override;
  void Close() override { open_ = false; }
  bool IsOpen() const override { return open_; }
  camera::StereoCameraInfo Info() const override;

 private:
  const KinematicRobot* robot_;
  const int width_;
  const int height_;
  const double rate_hz_;
  const Clock* clock_;
  bool open_ = false;
  uint64_t sequence_ = 0;
  SteadyTime next_;
};

}  // namespace mostar::testpattern
