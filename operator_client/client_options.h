// operator_client's command line over its configuration: the client configuration file turned
// into console options, then the flags' overrides. False with a message naming the key or flag.
#pragma once

#include <string>

#include "operator_client/client_config.pb.h"
#include "operator_client/ui/operator_console.h"

namespace mostar::client {

// The flags that change the console (the rest are wiring: domain, profile, trace, ...).
struct ClientFlags {
  std::string client_id = "operator";  // a valid client id; with DDS Security its cert's CN
  std::string role = "pilot";          // "pilot" or "observer"
  std::string display;                 // empty: the configuration's display_mode, else mono-left
  std::string calibration_path;        // --calibration: loaded and saved here; overrides the file's
  bool headless = false;
  bool calibration_panel = false;
  bool no_hud = false;
};

// The configuration file's part: calibration profile (relative to `config_dir`), AR features,
// vision, drive limits, intrinsics from the robot.
bool ConsoleOptionsFromConfig(const ClientConfig& config, const std::string& config_dir,
                              ui::ConsoleOptions* options, std::string* error);

// The flags over `options` (from ConsoleOptionsFromConfig of `config`).
bool ApplyClientFlags(const ClientFlags& flags, const ClientConfig& config,
                      ui::ConsoleOptions* options, std::string* error);

}  // namespace mostar::client
