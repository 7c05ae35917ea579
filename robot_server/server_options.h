// robot_server's command line over its configuration: the flags, their overrides of the
// ServerConfig, and the control loop's options from the configuration.
#pragma once

#include <string>

#include "robot_server/control/robot_controller.h"
#include "robot_server/drive/drive_config.h"
#include "robot_server/server_config.pb.h"

namespace CLI {
class App;
}

namespace mostar::server {

struct ServerFlags {
  std::string config_path;
  int domain = -1;  // < 0: from the configuration, then MOSTAR_DDS_DOMAIN
  std::string dds_profile;
  std::string source;  // "", "test_pattern", "sim", "hardware"
  std::string scene;   // --sim FILE
  double duration_s = 0;
  std::string log_level = "info";
  std::string trace_path;
  std::string record_path;
  std::string replay_path;
  double replay_rate = 1.0;
  bool replay_loop = false;
  bool replay_paused = false;
  std::string replay_sensors;
  std::string state_dir;      // --state-dir: overrides state_dir
  bool insecure = false;      // --insecure: sets dds.insecure
  bool check_config = false;  // --check-config: report problems and exit (server_check.h)
};

// robot_server's command-line flags into `flags`.
void AddServerFlags(CLI::App* app, ServerFlags* flags);

// The flags' overrides: --source, --sim (implies SIM), --replay-sensors (camera and laser
// replay of one file at --replay-rate, --loop), --state-dir, --insecure (dds.insecure; the flag
// can only turn it on). Paths on the command line are made
// absolute from the working directory (paths in the file stay relative to the file).
void ApplyFlags(const ServerFlags& flags, ServerConfig* config);

// Where the e-stop latch is kept (see state_dir in server_config.proto): the directory, or ""
// when it is not persisted (SIM or TEST_PATTERN without a state_dir, or with an empty one).
// False with a message for an empty state_dir with source HARDWARE. A relative state_dir is
// taken from `config_dir`.
bool EstopStateDirectory(const ServerConfig& config, const std::string& config_dir,
                         std::string* directory, std::string* error);

// The control loop's options: periods, holder timeout, DDS write-stall limit, drive settings
// and the intrinsics to publish.
RobotControllerOptions ControllerOptionsFrom(const ServerConfig& config,
                                             const drive::DriveSettings& settings,
                                             const std::vector<CameraIntrinsicsInfo>& intrinsics);

}  // namespace mostar::server
