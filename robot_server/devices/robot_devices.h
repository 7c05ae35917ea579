// Device selection: the concrete devices of the configured source (built-in test pattern,
// simulator, hardware), with the replay backends in place of the camera (camera.backend REPLAY)
// and the laser (laser.replay.file). Every member is behind its device interface, so the
// control loop and the camera pipeline run the same code whatever the source.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "common/types/stereo_frame.h"
#include "robot_server/bumper/bumper_belt.h"
#include "robot_server/camera/camera_pipeline.h"
#include "robot_server/camera/stereo_camera.h"
#include "robot_server/drive/drive_config.h"
#include "robot_server/drive/drive_motors.h"
#include "robot_server/laser/laser_scanner.h"
#include "robot_server/server_config.pb.h"
#include "robot_server/sim/sim_world.h"
#include "robot_server/sim_devices/sim_devices.h"
#include "robot_server/sonar/sonar_ring.h"
#include "robot_server/testpattern/test_pattern.h"

namespace mostar::server {

// The devices of one source. Null members are absent; `laser()` and `motors()` give the ones
// in use. Owns everything; destroy after the users stopped.
struct RobotDevices {
  std::unique_ptr<testpattern::KinematicRobot> pattern_robot;  // TEST_PATTERN: the motors
  std::unique_ptr<sim::SimWorld> world;                        // SIM
  std::unique_ptr<sim::SimulatedLms200> sim_laser;             // SIM, unless replayed
  std::unique_ptr<laser::LaserScanner> owned_laser;            // others (pattern, serial, replay)
  std::unique_ptr<drive::DriveMotors> owned_motors;            // SIM and HARDWARE
  std::unique_ptr<sim::SimulatedSonar> sim_sonar;              // SIM with sonar sensors
  std::unique_ptr<sonar::SonarRing> owned_sonar;               // HARDWARE with sonar sensors
  std::unique_ptr<bumper::BumperBelt> bumpers;                 // bumpers.backend not NONE
  std::unique_ptr<camera::StereoCamera> camera;                // moved into the camera pipeline
  camera::CameraPipelineOptions camera_options;
  // Intrinsics of each eye (left, right), published for the clients; empty when unknown.
  std::vector<CameraIntrinsicsInfo> intrinsics;

  laser::LaserScanner* laser() const;  // null when there is none
  drive::DriveMotors* motors() const;
  sonar::SonarRing* sonar() const;  // null when there is none
};

// Refuses sensor replay with the HARDWARE source: recorded (re-stamped) scans or images would
// steer the real motors. False with a message naming the keys and the alternatives.
bool CheckReplayIsNotOnHardware(const ServerConfig& config, std::string* error);

// The sonar belt and the bumper belt of `config` for its source (SIM: simulated in
// devices->world, which must exist; HARDWARE: SRF08s on Linux I2C, GPIO bumpers; TEST_PATTERN:
// none, whatever the sections say). False with a message naming the key when a bumper backend
// does not fit the source or a device cannot be opened.
bool MakeSonarAndBumpers(const ServerConfig& config, const Clock* clock, RobotDevices* devices,
                         std::string* error);

// Builds the devices of `config` (refused first by CheckReplayIsNotOnHardware). Files named in
// the configuration are relative to `config_dir`. The source may adjust the odometry geometry
// in `settings` (the simulated or pattern robot's). False with a message naming the key or
// device on failure.
bool MakeRobotDevices(const ServerConfig& config, const std::string& config_dir, const Clock* clock,
                      drive::DriveSettings* settings, RobotDevices* devices, std::string* error);

}  // namespace mostar::server
