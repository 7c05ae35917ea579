// The heads-up display (top left): video and scan rates, display age, link health, the pilot
// and watchdog, device problems, bumper contacts (flashing), sonar echoes the laser misses, the
// drive command, a faded overlay's reason, a waiting calibration proposal and the status line.
// ImGui; render thread.
#pragma once

#include <optional>
#include <string>

#include "common/time/time.h"
#include "operator_client/net/robot_state.h"
#include "operator_client/render/display_mode.h"
#include "operator_client/ui/drive_input.h"
#include "operator_client/video/stereo_receiver.h"

namespace mostar::ui {

// The console's own state the HUD shows.
struct HudStatus {
  bool has_pair = false;      // a pair is on screen
  SteadyTime pair_received;   // when it became complete here
  double display_age_ms = 0;  // capture-to-display age of the last new pair
  double frame_time_ms = 0;   // render time of the last frame
  render::DisplayMode mode = render::DisplayMode::kMonoLeft;
  std::string client_id;
  bool pilot = false;
  DriveOutput drive;        // the command being sent
  double drive_scale = 1;   // [0.1, 1]
  std::string status_line;  // may be empty
  // An e-stop engagement (true) or release (false) sent and not yet reported by the robot.
  std::optional<bool> pending_estop;
  // The robot stopped driving for this pilot and waits for a re-arm: why and what to do.
  std::string rearm_note;
  // This client runs a network DDS profile without DDS Security (--insecure): a warning line.
  bool dds_security_off = false;
  // Sonar sectors of the shown overlay: echoes, and those the laser does not see.
  size_t sonar_echoes = 0;
  size_t sonar_unseen = 0;
  // The overlay is drawn faded (not at the image's time) and why; empty otherwise.
  std::string overlay_note;
  // How the shown pair relates to its edge result (ResultNote); empty when it is in.
  std::string vision_note;
  // A trustworthy self-calibration proposal waits in the closed calibration panel (C).
  bool calibration_proposal = false;
};

// `now`: steady time, for the ages of the last samples.
void DrawHudPanel(const client::RobotSnapshot& robot, const client::ReceiverStats& video,
                  const HudStatus& status, SteadyTime now);

}  // namespace mostar::ui
