// operator_client's command line: every option, its checks and its default, parsed into one
// struct. client_main.cc wires what it says; nothing here opens a device, a window or DDS.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "operator_client/client_options.h"

namespace mostar::client {

struct ClientCommandLine {
  int domain = -1;  // -1: MOSTAR_DDS_DOMAIN, then 0
  std::string dds_profile = "loopback";
  ClientFlags flags;        // the flags that change the console
  std::string config_path;  // empty: the built-in defaults
  bool check_config = false;
  // With --video-via-relay the camera streams come from mostar_relay on video_domain (-1:
  // domain + 1); commands and the rest stay direct.
  bool video_via_relay = false;
  int video_domain = -1;
  // The run ends after max_frames rendered pairs (0: no limit) or duration_s (0: none).
  int max_frames = 0;
  double duration_s = 0;
  // Without the robot for this long, join DDS again as a new participant, then after twice as
  // long each time (RejoinPolicy); 0: never.
  double rejoin_after_s = 15;
  std::string screenshot;              // PNG of the last rendered frame, written at the end
  int64_t capture_stamp_ns = -1;       // render only this pair (ns since the epoch), then end
  int capture_after = -1;              // capture the first pair decoded after this many
  std::vector<double> scripted_drive;  // V, W (m/s, rad/s) held throughout, or empty
  std::string trace_path;
  std::string record_path;
  std::string log_level = "info";
  int strength_ignored = 0;  // --strength: accepted for old scripts, the role table decides

  bool capture() const { return capture_stamp_ns >= 0 || capture_after >= 0; }
};

// Declares every option on `app`, writing into `line` when `app` parses.
void AddClientOptions(CLI::App* app, ClientCommandLine* line);

}  // namespace mostar::client
