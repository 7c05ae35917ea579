// What the console shows of the bumper belt: per-segment looks for the robot outline in the map
// and a status line for the HUD, from the robot's latest BumperState. Pure: no ImGui.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/time/time.h"
#include "common/types/bumper.h"

namespace mostar::ui {

enum class SegmentLook {
  kIdle,     // not touched
  kPressed,  // pressed now (flashing)
  kLatched,  // its contact stopped the robot; released, waiting for the pilot's re-arm
};

struct BumperView {
  std::vector<SegmentLook> segments;  // one per segment of the belt; empty when it has none
  bool alert = false;                 // some segment pressed or latched, or the belt unreadable
  bool flash_on = false;              // blink phase of alerting segments and lines (2 Hz)
  bool stale = false;  // no bumper state for kBumperStaleAfter: the looks are the last known
  std::string status;  // HUD line; empty when there is nothing to say
};

// The robot announces its bumpers on change and at 1 Hz.
inline constexpr Duration kBumperStaleAfter = std::chrono::seconds(3);

// Direction of segment `i` of `count` as seen from the robot, one of eight: "front",
// "front-left", "left", "rear-left", "rear", "rear-right", "right", "front-right".
const char* SegmentDirection(int i, int count);

// `received`: when `state` arrived here; `now`: steady time.
BumperView ViewBumpers(const std::optional<BumperState>& state, SteadyTime received,
                       SteadyTime now);

}  // namespace mostar::ui
