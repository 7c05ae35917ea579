// The page's HUD from what the observer knows of the robot. Pure: clocks come in as arguments.
#pragma once

#include <optional>

#include "common/time/time.h"
#include "operator_client/net/robot_state.h"
#include "operator_client/web/web_messages.h"

namespace mostar::web {

// Streams older than this count as lost for the link state.
constexpr Duration kStaleAfter = std::chrono::seconds(3);

struct HudInputs {
  std::optional<Time> newest_pair_stamp;           // capture stamp of the newest pair received
  std::optional<SteadyTime> newest_pair_received;  // when it arrived here
  double video_fps = 0;
  uint64_t browsers = 0;
  bool dds_security_off = false;
  double footprint_radius_m = 0;  // the robot outline on the map, metres
};

// The link state is "no contact" when no health arrived for kStaleAfter, else "no video" or
// "no scans" when that stream is stale, else "ok". The bumpers are the console's view of the
// robot's latest BumperState (ui::ViewBumpers).
HudState MakeHud(const client::RobotSnapshot& robot, const HudInputs& inputs, Time now,
                 SteadyTime steady_now);

}  // namespace mostar::web
