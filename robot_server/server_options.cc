#include "robot_server/server_options.h"

#include <CLI/CLI.hpp>

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
    BeltsReplayConfig* belts = config->mutable_belts_replay();
    belts->set_file(file);
    belts->set_rate(flags.replay_rate);
    belts->set_loop(flags.replay_loop);
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

void AddServerFlags(CLI::App* app, ServerFlags* f) {
  app->add_option("--record", f->record_path,
                  "record everything published (and accepted commands)");
  auto* replay =
      app->add_option("--replay", f->replay_path, "publish this recording instead of live devices")
          ->check(CLI::ExistingFile);
  app->add_option("--replay-sensors", f->replay_sensors,
                  "camera and laser from this recording (with --replay-rate, --loop), motors "
                  "and odometry from the source: the live pipeline on recorded data")
      ->check(CLI::ExistingFile)
      ->excludes(replay);
  app->add_option("--replay-rate", f->replay_rate, "replay speed factor")
      ->check(CLI::PositiveNumber);
  app->add_flag("--loop", f->replay_loop, "replay (--replay, --replay-sensors) in a loop");
  app->add_flag("--replay-paused", f->replay_paused,
                "start the replay paused; control it on stdin: p pause/resume, s [N] step, "
                "r RATE, q quit");
  app->add_option("-c,--config", f->config_path, "server configuration (protobuf text format)")
      ->check(CLI::ExistingFile);
  app->add_option("--domain", f->domain, "DDS domain id (default: config, then MOSTAR_DDS_DOMAIN)")
      ->check(CLI::Range(0, 232));
  app->add_option("--dds-profile", f->dds_profile, "'loopback' or a Fast DDS XML profiles file");
  app->add_option("--source", f->source, "test_pattern | sim | hardware (overrides the config)")
      ->check(CLI::IsMember({"test_pattern", "sim", "hardware"}));
  app->add_option("--sim", f->scene, "run the simulated robot in this scene (implies --source sim)")
      ->check(CLI::ExistingFile);
  app->add_option("--duration", f->duration_s,
                  "stop after this many seconds (0 = run until signal)")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--log-level", f->log_level, "debug | info | warning | error")
      ->check(CLI::IsMember({"debug", "info", "warning", "error"}));
  app->add_option("--trace", f->trace_path,
                  "write published stamps and accepted commands to this CSV");
  app->add_flag("--insecure", f->insecure,
                "allow a network DDS profile without DDS Security (anyone on the network can "
                "read and command the robot; docs/security.md)");
  app->add_option("--state-dir", f->state_dir,
                  "keep the e-stop latch in this directory (default: state_dir of the config, "
                  "/var/lib/mostar for the hardware source)");
  app->add_flag("--check-config", f->check_config,
                "check the configuration, the files and devices it names, the role table and "
                "the DDS profile (certificates, addresses), print each problem with its fix, "
                "and exit: 0 when all is well, 1 otherwise; opens no device, starts no DDS");
}

}  // namespace mostar::server
