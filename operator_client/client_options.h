// operator_client's command line over its configuration: the client configuration file turned
// into console options, then the flags' overrides. False with a message naming the key or flag.
#pragma once

#include <string>
#include <vector>

#include "common/config/config_report.h"
#include "common/dds/participant.h"
#include "operator_client/client_config.pb.h"
#include "operator_client/ui/operator_console.h"

namespace mostar::client {

// The flags that change the console (the rest are wiring: domain, profile, trace, ...).
struct ClientFlags {
  std::string client_id = "operator";  // a valid client id; with DDS Security its cert's CN
  bool client_id_given = false;        // --id was on the command line
  bool insecure = false;               // --insecure: a network profile without DDS Security
  std::string role = "pilot";          // "pilot" or "observer"
  std::string display;                 // empty: the configuration's display_mode, else mono-left
  std::string calibration_path;        // --calibration: loaded and saved here; overrides the file's
  bool headless = false;
  bool calibration_panel = false;
  bool no_hud = false;
  std::vector<int> window_size;  // --window-size W x H in pixels; empty: the image's size
};

// The configuration file's part: calibration profile (relative to `config_dir`), AR features,
// vision, drive limits, intrinsics from the robot.
bool ConsoleOptionsFromConfig(const ClientConfig& config, const std::string& config_dir,
                              ui::ConsoleOptions* options, std::string* error);

// The flags over `options` (from ConsoleOptionsFromConfig of `config`).
bool ApplyClientFlags(const ClientFlags& flags, const ClientConfig& config,
                      ui::ConsoleOptions* options, std::string* error);

// The window: --window-size, else sized for the display mode and the calibration's image
// (render::WindowSizeFor); hidden when headless, quad-buffered for quad-buffer stereo.
ui::WindowOptions WindowOptionsFor(const ClientFlags& flags, const ui::ConsoleOptions& options);

// The client id this client sends as sender_id and shows in the lease. Without DDS Security
// (`secure` false): --id (default "operator"). With it the robot drops every sample whose
// sender_id is not the CN of the writer's certificate, so: the CN (`certificate_cn`, empty
// when the certificate names no valid client id, which is refused), and an --id other than
// the CN is refused. False with a message.
bool ResolveClientId(const ClientFlags& flags, bool secure, const std::string& certificate_cn,
                     std::string* client_id, std::string* error);

// operator_client --check-config: the configuration file at `config_path` (may be empty) with
// its calibration, the flags over it, the DDS profile `dds` and, with --video-via-relay, the
// relay's `video_dds` (certificates, addresses: dds::CheckDdsProfile), the client id against
// the certificate, and a display for a window. Results go to `report`.
void CheckConsoleConfig(const std::string& config_path, const ClientFlags& flags,
                        const dds::ParticipantOptions& dds,
                        const dds::ParticipantOptions* video_dds, ConfigReport* report);

}  // namespace mostar::client
