#include "robot_server/server_options.h"

#include "common/config/config_paths.h"

namespace mostar::server {

void ApplyFlags(const ServerFlags& flags, ServerConfig* config) {
  if (flags.source == "test_pattern") config->set_source(ServerConfig::TEST_PATTERN);
  if (flags.source == "sim") config->set_source(ServerConfig::SIM);
  if (flags.source == "hardware") config->set_source(ServerConfig::HARDWARE);
  if (!flags.scene.empty()) {
    config->set_source(ServerConfig::SIM);
    config->set_scene_file(AbsoluteFromWorkingDirectory(flags.scene));
  }
  if (!flags.replay_sensors.empty()) {
    const std::string file = AbsoluteFromWorkingDirectory(flags.replay_sensors);
    camera::CameraConfig* camera_config = config->mutable_camera();
    camera_config->set_backend(camera::CameraConfig::REPLAY);
    camera_config->mutable_replay()->set_file(file);
    camera_config->mutable_replay()->set_rate(flags.replay_rate);
    camera_config->mutable_replay()->set_loop(flags.replay_loop);
    laser::LaserReplayConfig* laser_replay = config->mutable_laser()->mutable_replay();
    laser_replay->set_file(file);
    laser_replay->set_rate(flags.replay_rate);
    laser_replay->set_loop(flags.replay_loop);
  }
  if (flags.insecure) config->mutable_dds()->set_insecure(true);
  if (!flags.state_dir.empty()) {
    config->set_state_dir(AbsoluteFromWorkingDirectory(flags.state_dir));
  }
}

bool EstopStateDirectory(const ServerConfig& config, const std::string& config_dir,
                         std::string* directory, std::string* error) {
  directory->clear();
  if (config.source() != ServerConfig::HARDWARE && !config.has_state_dir()) return true;
  if (config.state_dir().empty()) {
    if (config.source() != ServerConfig::HARDWARE) return true;
    *error =
        "state_dir: empty; the hardware robot keeps its e-stop latch there "
        "(default /var/lib/mostar)";
    return false;
  }
  *directory = ResolveRelativeTo(config.state_dir(), config_dir);
  return true;
}

RobotControllerOptions ControllerOptionsFrom(const ServerConfig& config,
                                             const drive::DriveSettings& settings,
                                             const std::vector<CameraIntrinsicsInfo>& intrinsics) {
  RobotControllerOptions options;
  options.robot_id = config.robot_id();
  options.health_period = FromSeconds(config.health_period_s());
  options.lease_period = FromSeconds(config.lease_period_s());
  options.holder_timeout = FromSeconds(config.holder_timeout_s());
  options.write_stall_limit = FromSeconds(config.dds().write_stall_exit_s());
  options.odometry = settings.odometry;
  options.safety = settings.safety;
  options.roles = settings.roles;
  options.intrinsics = intrinsics;
  return options;
}

}  // namespace mostar::server
