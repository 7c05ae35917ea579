// The simulated world seen through the robot's device interfaces, so that robot_server runs the
// same code paths with the simulator as with hardware:
//   SimStereoCamera  : camera::StereoCamera  (renders both eyes at the frame rate)
//   SimDriveMotors   : drive::DriveMotors    (velocity commands in, encoder ticks out)
//   SimulatedLms200  : the LMS200 emulator on a pseudo-terminal, fed by SimWorldRangeSource,
//                      read by the real LMS200 driver (Lms200Scanner over libserial)
//   SimBumperBelt    : bumper::BumperBelt     (segments touching an obstacle in the scene)
//   SimulatedSonar   : the real SRF08 driver (Srf08Ring) on an emulated I2C bus of SRF08s
//                      whose echoes SimWorld raycasts at each sensor's mount
// All share one SimWorld, which they advance to the current time of the injected clock.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "common/time/time.h"
#include "robot_server/bumper/bumper_belt.h"
#include "robot_server/camera/stereo_camera.h"
#include "robot_server/drive/drive_motors.h"
#include "robot_server/laser/lms200_config.pb.h"
#include "robot_server/laser/lms200_scanner.h"
#include "robot_server/sim/lms200_emulator/lms200_emulator.h"
#include "robot_server/sim/lms200_emulator/lms200_pty.h"
#include "robot_server/sim/lms200_emulator/range_source.h"
#include "robot_server/sim/sim_range_source.h"
#include "robot_server/sim/sim_world.h"
#include "robot_server/sonar/sonar_config.pb.h"
#include "robot_server/sonar/srf08.h"

namespace mostar::sim {

class SimStereoCamera final : public camera::StereoCamera {
 public:
  SimStereoCamera(SimWorld* world, double rate_hz, const Clock* clock);
  bool Open(std::string* error) override;
  camera::GrabResult Grab(Duration timeout, camera::StereoImagePair* pair) override;
  void Close() override { open_ = false; }
  bool IsOpen() const override { return open_; }
  camera::StereoCameraInfo Info() const override;

 private:
  SimWorld* world_;
  const double rate_hz_;
  const Clock* clock_;
  bool open_ = false;
  uint64_t sequence_ = 0;
  SteadyTime next_;
};

class SimDriveMotors final : public drive::DriveMotors {
 public:
  SimDriveMotors(SimWorld* world, const Clock* clock);
  bool SetWheelVelocities(const drive::WheelVelocities& wheels, std::string* error) override;
  bool SetVelocity(double linear_mps, double angular_radps, std::string* error) override;
  bool Stop(std::string* error, bool clear_faults = false) override;
  drive::MotorStatus Status() const override;
  // A fault is a collision; counts the collisions.
  DeviceHealth Health() const override;
  bool ReadEncoders(drive::EncoderReading* reading, std::string* error) override;
  int counter_bits() const override;

 private:
  SimWorld* world_;
  const Clock* clock_;
};

// The simulated LMS200 as the robot sees it: the emulator on a pseudo-terminal (symlinked at
// `link_path`) and the real driver (Lms200Scanner over libserial) reading it.
class SimulatedLms200 {
 public:
  // Null with a message when the pseudo-terminal cannot be created. `line` sets the emulated
  // link's fault rates (sim_config.proto, LaserConfig.line_*).
  static std::unique_ptr<SimulatedLms200> Create(SimWorld* world, laser::Lms200Config config,
                                                 const std::string& link_path, const Clock* clock,
                                                 std::string* error,
                                                 const proto::LaserConfig& line = {});
  ~SimulatedLms200();
  laser::LaserScanner* scanner() { return scanner_.get(); }
  Lms200Emulator* emulator() { return emulator_.get(); }
  Lms200PtyRunner* pty() { return runner_.get(); }

 private:
  SimulatedLms200() = default;
  std::unique_ptr<SimWorldRangeSource> ranges_;
  std::unique_ptr<Lms200Emulator> emulator_;
  std::unique_ptr<Lms200PtyRunner> runner_;
  std::unique_ptr<laser::Lms200Scanner> scanner_;
};

class SimBumperBelt final : public bumper::BumperBelt {
 public:
  SimBumperBelt(SimWorld* world, int segments, const Clock* clock)
      : world_(world), segments_(segments), clock_(clock) {}
  bool Read(uint32_t* pressed, std::string* error) override;
  int segments() const override { return segments_; }
  DeviceHealth Health() const override;

 private:
  SimWorld* world_;
  const int segments_;
  const Clock* clock_;
  std::atomic<uint32_t> last_{0};
  std::atomic<uint64_t> reads_{0};
};

// The simulated sonar belt as the robot sees it (see the top of this file). The sensors'
// cone (beam angle from the configuration) and height come from `cone`.
class SimulatedSonar {
 public:
  // Null with a message when the configuration is invalid (sonar_config.h).
  static std::unique_ptr<SimulatedSonar> Create(SimWorld* world, const sonar::SonarConfig& config,
                                                SonarCone cone, const Clock* clock,
                                                std::string* error);
  sonar::SonarRing* ring() { return ring_.get(); }

 private:
  SimulatedSonar() = default;
  std::unique_ptr<sonar::Srf08Ring> ring_;
};

}  // namespace mostar::sim
