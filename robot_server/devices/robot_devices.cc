#include "robot_server/devices/robot_devices.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "common/config/config_paths.h"
#include "common/log/log.h"
#include "robot_server/bumper/gpiod_bumper_belt.h"
#include "robot_server/camera/camera_factory.h"
#include "robot_server/camera/camera_intrinsics.h"
#include "robot_server/drive/serial_drive_motors.h"
#include "robot_server/laser/lms200_scanner.h"
#include "robot_server/replay/replay_laser_scanner.h"
#include "robot_server/replay/replay_sonar.h"
#include "robot_server/replay/replay_stereo_camera.h"
#include "robot_server/replay/replay_timeline.h"
#include "robot_server/sim/scene.h"
#include "robot_server/sonar/linux_i2c_bus.h"
#include "robot_server/sonar/sonar_config.h"
#include "robot_server/sonar/srf08.h"

namespace mostar::server {
namespace {

CameraIntrinsicsInfo InfoFromIntrinsics(const camera::CameraIntrinsics& k, Eye eye) {
  CameraIntrinsicsInfo info;
  info.frame_id = eye == Eye::kLeft ? "camera_left" : "camera_right";
  info.width_px = k.image_size.width;
  info.height_px = k.image_size.height;
  info.fx = k.camera_matrix(0, 0);
  info.fy = k.camera_matrix(1, 1);
  info.cx = k.camera_matrix(0, 2);
  info.cy = k.camera_matrix(1, 2);
  info.distortion = k.distortion;
  return info;
}

bool ReplaysCamera(const ServerConfig& config) {
  return config.camera().backend() == camera::CameraConfig::REPLAY;
}
bool ReplaysLaser(const ServerConfig& config) { return !config.laser().replay().file().empty(); }
bool ReplaysBelts(const ServerConfig& config) {
  return !config.belts_replay().file().empty() && config.source() == ServerConfig::SIM &&
         (config.sonar().sensors_size() > 0 || config.bumpers().backend() != BumperConfig::NONE);
}

// Built-in video sources (test pattern, simulator): the codec of `camera.codec` (with its
// `camera.h264` options) at the source's `frame_rate_hz`; the bitrate control of
// `camera.bitrate` when the configuration has one (e.g. a WAN target), else the defaults; JPEG
// quality starts at `initial_quality`; the resolution ladder for images `width_px` wide unless
// one is configured.
void UseConfiguredBitrate(const ServerConfig& config, int initial_quality, int width_px,
                          camera::CameraPipelineOptions* options) {
  const camera::CameraPipelineOptions configured = camera::MakePipelineOptions(config.camera());
  if (config.camera().has_bitrate()) {
    options->bitrate_classes = configured.bitrate_classes;
    options->bitrate = configured.bitrate;
  }
  options->codec = configured.codec;
  options->h264 = configured.h264;
  options->frame_rate_hz =
      std::max(1, static_cast<int>(std::lround(config.test_pattern().frame_rate_hz())));
  if (config.camera().bitrate().scales_size() == 0) {
    options->bitrate.scales = camera::DefaultScaleLadder(width_px);
  }
  options->bitrate.initial_quality =
      std::clamp(initial_quality, options->bitrate.min_quality, options->bitrate.max_quality);
}

bool MakeTestPatternDevices(const ServerConfig& config, const Clock* clock,
                            drive::DriveSettings* settings, RobotDevices* devices) {
  const TestPatternConfig& tp = config.test_pattern();
  testpattern::RoomOptions room;
  room.wheel_radius_m = settings->odometry.wheel_radius_m;
  room.track_width_m = settings->odometry.track_width_m;
  room.ticks_per_turn = static_cast<int>(settings->odometry.ticks_per_turn);
  settings->odometry.counter_bits = 16;
  devices->pattern_robot = std::make_unique<testpattern::KinematicRobot>(room, clock);
  if (!ReplaysCamera(config)) {
    devices->camera = std::make_unique<testpattern::TestPatternCamera>(
        devices->pattern_robot.get(), tp.width_px(), tp.height_px(), tp.frame_rate_hz(), clock);
  }
  UseConfiguredBitrate(config, tp.jpeg_quality(), tp.width_px(), &devices->camera_options);
  if (!ReplaysLaser(config)) {
    devices->owned_laser = std::make_unique<testpattern::TestPatternLaser>(
        devices->pattern_robot.get(), tp.scan_rate_hz(), clock);
  }
  return true;
}

bool MakeSimDevices(const ServerConfig& config, const std::string& config_dir, const Clock* clock,
                    drive::DriveSettings* settings, RobotDevices* devices, std::string* error) {
  if (config.scene_file().empty()) {
    *error = "source SIM needs a scene: --sim FILE or scene_file in the configuration";
    return false;
  }
  sim::proto::Scene scene;
  if (!sim::LoadScene(ResolveConfigPath(config.scene_file(), config_dir), &scene, error)) {
    return false;
  }
  if (!sim::ValidateSimConfig(config.sim(), "sim", error)) return false;
  devices->world = sim::SimWorld::Create(scene, config.sim(), clock->Now(), error);
  if (!devices->world) return false;
  // Odometry uses the simulated robot's geometry.
  const auto& drive = devices->world->drive_params();
  settings->odometry.wheel_radius_m = drive.wheel_radius_m;
  settings->odometry.track_width_m = drive.track_width_m;
  settings->odometry.ticks_per_turn = drive.encoder_pulses_per_turn;
  settings->odometry.counter_bits = drive.encoder_counter_bits;
  settings->odometry.axle_x_m = drive.axle_x_m;
  devices->owned_motors = std::make_unique<sim::SimDriveMotors>(devices->world.get(), clock);
  if (!ReplaysCamera(config)) {
    devices->camera = std::make_unique<sim::SimStereoCamera>(
        devices->world.get(), config.test_pattern().frame_rate_hz(), clock);
  }
  const sim::LaserCameraCalibration& truth = devices->world->calibration();
  UseConfiguredBitrate(config, config.test_pattern().jpeg_quality(), truth.width_px,
                       &devices->camera_options);
  for (const Eye eye : {Eye::kLeft, Eye::kRight}) {
    CameraIntrinsicsInfo info;
    info.frame_id = eye == Eye::kLeft ? "camera_left" : "camera_right";
    info.width_px = truth.width_px;
    info.height_px = truth.height_px;
    info.fx = info.fy = truth.focal_px;
    info.cx = truth.cx_px;
    info.cy = eye == Eye::kLeft ? truth.cy_px : truth.right_cy_px;
    info.distortion = {truth.k1, truth.k2, 0, 0, 0};
    devices->intrinsics.push_back(info);
  }
  if (ReplaysLaser(config)) return true;
  // One emulator link per process, so that several simulated robots can run side by side.
  const std::string link =
      config.sim_laser_link() + "-" + std::to_string(static_cast<long>(getpid()));
  devices->sim_laser = sim::SimulatedLms200::Create(devices->world.get(), config.laser(), link,
                                                    clock, error, config.sim().laser());
  return devices->sim_laser != nullptr;
}

bool MakeHardwareDevices(const ServerConfig& config, const std::string& config_dir,
                         const Clock* clock, drive::DriveSettings* settings, RobotDevices* devices,
                         std::string* error) {
  if (!ReplaysCamera(config)) {
    devices->camera = camera::MakeStereoCamera(config.camera(), clock, error);
    if (!devices->camera) return false;
  }
  devices->camera_options = camera::MakePipelineOptions(config.camera());
  const std::string files[2] = {config.camera().left_intrinsics_file(),
                                config.camera().right_intrinsics_file()};
  for (int e = 0; e < 2 && !files[0].empty() && !files[1].empty(); ++e) {
    camera::CameraIntrinsics k;
    if (!camera::LoadCameraIntrinsics(ResolveConfigPath(files[e], config_dir), &k, error)) {
      return false;
    }
    const camera::StereoCameraInfo camera_info =
        devices->camera ? devices->camera->Info() : camera::StereoCameraInfo{};
    if (camera_info.width_px > 0) k = k.ScaledTo({camera_info.width_px, camera_info.height_px});
    devices->intrinsics.push_back(InfoFromIntrinsics(k, e == 0 ? Eye::kLeft : Eye::kRight));
  }
  if (!ReplaysLaser(config)) {
    devices->owned_laser = laser::MakeSerialLms200Scanner(config.laser(), clock);
    if (!devices->owned_laser) {
      *error = "cannot create the LMS200 driver for " + config.laser().port();
      return false;
    }
  }
  auto motors = drive::SerialDriveMotors::Open(*clock, settings->motors, error);
  if (!motors) return false;
  devices->owned_motors = std::move(motors);
  return true;
}

// The replay backends in place of the source's camera, laser and belts. The replays of one
// file share a timeline (and must agree on its rate and loop).
bool MakeReplayDevices(const ServerConfig& config, const std::string& config_dir,
                       const Clock* clock, RobotDevices* devices, std::string* error) {
  std::map<std::string, std::shared_ptr<replay::ReplayTimeline>> timelines;
  // The options common to the replay devices; false (error set) when the file is unusable.
  auto replay_device = [&](const std::string& key, const std::string& file, double rate, bool loop,
                           replay::ReplayDeviceOptions* options) {
    options->path = ResolveConfigPath(file, config_dir);
    options->clock = clock;
    auto it = timelines.find(options->path);
    if (it != timelines.end()) {
      if (it->second->options().rate != rate || it->second->options().loop != loop) {
        *error = key + ": the replays (camera, laser, belts) of " + options->path +
                 " must have the same rate and loop";
        return false;
      }
      options->timeline = it->second;
      return true;
    }
    replay::ReplayTimelineOptions timeline_options;
    timeline_options.rate = rate;
    timeline_options.loop = loop;
    options->timeline =
        replay::ReplayTimeline::ForRecording(options->path, *clock, timeline_options, error);
    if (!options->timeline) {
      *error = key + ": " + *error;
      return false;
    }
    timelines[options->path] = options->timeline;
    return true;
  };
  if (ReplaysCamera(config)) {
    if (!camera::ValidateCameraConfig(config.camera(), error)) {
      *error = "camera." + *error;
      return false;
    }
    const camera::ReplayCameraConfig& r = config.camera().replay();
    replay::ReplayStereoCamera::Options options;
    if (!replay_device("camera.replay.file", r.file(), r.rate(), r.loop(), &options)) return false;
    options.due_at_stamp = r.deliver_at_capture_time();
    devices->camera = std::make_unique<replay::ReplayStereoCamera>(options);
    devices->camera_options = camera::MakePipelineOptions(config.camera());
    MOSTAR_LOG(INFO) << "camera: replaying " << options.path << " at " << r.rate() << "x"
                     << (r.loop() ? ", looping" : "")
                     << (options.due_at_stamp ? ", each pair at its capture stamp" : "");
  }
  if (ReplaysLaser(config)) {
    const laser::LaserReplayConfig& r = config.laser().replay();
    replay::ReplayLaserScanner::Options options;
    if (!replay_device("laser.replay.file", r.file(), r.rate(), r.loop(), &options)) return false;
    devices->owned_laser = std::make_unique<replay::ReplayLaserScanner>(options);
    MOSTAR_LOG(INFO) << "laser: replaying " << options.path << " at " << r.rate() << "x"
                     << (r.loop() ? ", looping" : "");
  }
  if (ReplaysBelts(config)) {
    const BeltsReplayConfig& r = config.belts_replay();
    replay::ReplayDeviceOptions options;
    if (!replay_device("belts_replay.file", r.file(), r.rate(), r.loop(), &options)) return false;
    if (config.sonar().sensors_size() > 0) {
      replay::ReplaySonarRing::Options sonar;
      static_cast<replay::ReplayDeviceOptions&>(sonar) = options;
      devices->sim_sonar.reset();
      devices->owned_sonar = std::make_unique<replay::ReplaySonarRing>(sonar);
    }
    if (config.bumpers().backend() != BumperConfig::NONE) {
      replay::ReplayBumperBelt::Options bumpers;
      static_cast<replay::ReplayDeviceOptions&>(bumpers) = options;
      bumpers.segments = devices->bumpers ? devices->bumpers->segments() : 16;
      std::string why;
      devices->bumpers = std::make_unique<replay::ReplayBumperBelt>(bumpers, &why);
      if (!why.empty()) MOSTAR_LOG(ERROR) << "bumpers: replay: " << why;
    }
    MOSTAR_LOG(INFO) << "sonar and bumper belts: replaying " << options.path << " at " << r.rate()
                     << "x" << (r.loop() ? ", looping" : "");
  }
  return true;
}

}  // namespace

laser::LaserScanner* RobotDevices::laser() const {
  if (owned_laser) return owned_laser.get();
  return sim_laser ? sim_laser->scanner() : nullptr;
}

drive::DriveMotors* RobotDevices::motors() const {
  return pattern_robot ? pattern_robot.get() : owned_motors.get();
}

sonar::SonarRing* RobotDevices::sonar() const {
  if (owned_sonar) return owned_sonar.get();
  return sim_sonar ? sim_sonar->ring() : nullptr;
}

bool MakeSonarAndBumpers(const ServerConfig& config, const Clock* clock, RobotDevices* devices,
                         std::string* error) {
  const ServerConfig::Source source = config.source();
  const BumperConfig& b = config.bumpers();
  if (source == ServerConfig::TEST_PATTERN) {
    if (config.sonar().sensors_size() > 0 || b.backend() != BumperConfig::NONE) {
      MOSTAR_LOG(INFO) << "source TEST_PATTERN: no sonar belt and no bumpers (the sonar and "
                          "bumpers sections are for SIM and HARDWARE)";
    }
    return true;
  }
  if (b.backend() == BumperConfig::GPIOD && source != ServerConfig::HARDWARE) {
    *error = "bumpers.backend GPIOD needs source HARDWARE (use SIM with the simulator)";
    return false;
  }
  if (b.backend() == BumperConfig::SIM && source != ServerConfig::SIM) {
    *error = "bumpers.backend SIM needs source SIM (GPIOD or NONE on the robot)";
    return false;
  }
  if (b.backend() == BumperConfig::GPIOD) {
    bumper::GpiodBumperOptions options;
    options.chip = b.chip();
    options.lines.assign(b.line().begin(), b.line().end());
    options.active_low = b.active_low();
    if (!options.IsValid(error)) {
      *error = "bumpers: " + *error;
      return false;
    }
    devices->bumpers = bumper::GpiodBumperBelt::Open(options, error);
    if (!devices->bumpers) {
      *error = "bumpers: " + *error;
      return false;
    }
  } else if (b.backend() == BumperConfig::SIM) {
    devices->bumpers =
        std::make_unique<sim::SimBumperBelt>(devices->world.get(), b.segments(), clock);
  }
  if (config.sonar().sensors_size() == 0) return true;
  if (source == ServerConfig::SIM) {
    devices->sim_sonar =
        sim::SimulatedSonar::Create(devices->world.get(), config.sonar(), {}, clock, error);
    if (!devices->sim_sonar) *error = "sonar: " + *error;
    return devices->sim_sonar != nullptr;
  }
  sonar::Srf08RingOptions options;
  if (!sonar::Srf08RingOptionsFromConfig(config.sonar(), &options, error)) {
    *error = "sonar: " + *error;
    return false;
  }
  std::unique_ptr<sonar::LinuxI2cBus> bus = sonar::LinuxI2cBus::Open(config.sonar().bus(), error);
  if (!bus) {
    *error = "sonar.bus: " + *error;
    return false;
  }
  devices->owned_sonar = std::make_unique<sonar::Srf08Ring>(std::move(bus), options, *clock);
  return true;
}

bool CheckReplayIsNotOnHardware(const ServerConfig& config, std::string* error) {
  if (config.source() != ServerConfig::HARDWARE) return true;
  std::string replayed;
  if (ReplaysLaser(config)) replayed = "laser.replay.file";
  if (ReplaysCamera(config))
    replayed += (replayed.empty() ? "" : " and ") + std::string("camera.backend REPLAY");
  if (!config.belts_replay().file().empty())
    replayed += (replayed.empty() ? "" : " and ") + std::string("belts_replay.file");
  if (replayed.empty()) return true;
  *error = "sensor replay (" + replayed +
           ", or --replay-sensors) is refused with source HARDWARE: recorded scans and images "
           "would drive the real motors. Replay with --source sim or test_pattern, or publish the "
           "recording alone with --replay";
  return false;
}

bool MakeRobotDevices(const ServerConfig& config, const std::string& config_dir, const Clock* clock,
                      drive::DriveSettings* settings, RobotDevices* devices, std::string* error) {
  if (!CheckReplayIsNotOnHardware(config, error)) return false;
  bool made = false;
  switch (config.source()) {
    case ServerConfig::TEST_PATTERN:
      made = MakeTestPatternDevices(config, clock, settings, devices);
      break;
    case ServerConfig::SIM:
      made = MakeSimDevices(config, config_dir, clock, settings, devices, error);
      break;
    case ServerConfig::HARDWARE:
      made = MakeHardwareDevices(config, config_dir, clock, settings, devices, error);
      break;
    default:
      *error = "unknown source";
      return false;
  }
  return made && MakeSonarAndBumpers(config, clock, devices, error) &&
         MakeReplayDevices(config, config_dir, clock, devices, error);
}

}  // namespace mostar::server
