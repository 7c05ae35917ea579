// Why the robot stopped driving for this pilot, and the way back (docs/safety.md, G5 and G7).
// After a link loss (commands late or missing: deadman, a lost command stream), a bumper
// contact or an e-stop release the robot waits for a re-arm (WAIT_REARM): one command with
// enable = false. The interactive console sends those whenever no drive key is held, so the
// pilot re-arms by letting go of the keys; the HUD says so. A scripted drive (--drive) re-arms
// by itself like such a pilot: enable = false for kRelease, then its command again, at most
// once per health the robot sends after the previous re-arm. Pure: the caller passes the
// robot's latest state and the time.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "common/time/time.h"
#include "common/types/health.h"

namespace mostar::ui {

class RearmGuide {
 public:
  // Three command periods: the robot sees enable = false before enable = true again.
  static constexpr Duration kRelease = std::chrono::milliseconds(150);

  struct Advice {
    std::string hud_text;        // empty: nothing to say
    bool hold_disarmed = false;  // a scripted drive sends enable = false now
  };

  // `holding`: this console holds the lease; `state`, `health_received`: the watchdog state of
  // the robot's latest health and when it arrived (nullopt: none yet); `keys_held`: the pilot's
  // current command has enable = true; `scripted`: a scripted drive; `now`: steady time.
  Advice Update(bool holding, std::optional<WatchdogState> state, SteadyTime health_received,
                bool keys_held, bool scripted, SteadyTime now);

  uint64_t scripted_rearms() const { return scripted_rearms_; }

 private:
  std::optional<SteadyTime> release_until_;
  std::optional<SteadyTime> last_release_end_;
  uint64_t scripted_rearms_ = 0;
};

}  // namespace mostar::ui
