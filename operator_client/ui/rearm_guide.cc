#include "operator_client/ui/rearm_guide.h"

namespace mostar::ui {

RearmGuide::Advice RearmGuide::Update(bool holding, std::optional<WatchdogState> state,
                                      SteadyTime health_received, bool keys_held, bool scripted,
                                      SteadyTime now) {
  Advice advice;
  if (release_until_ && now < *release_until_) {
    advice.hold_disarmed = true;
    advice.hud_text = "re-arming after the robot stopped driving";
    return advice;
  }
  release_until_.reset();
  if (!holding || state != WatchdogState::kWaitRearm) return advice;
  // A health that left the robot before the last re-arm still says WAIT_REARM: wait for the
  // next one.
  const bool before_last_rearm = last_release_end_ && health_received <= *last_release_end_;
  if (scripted) {
    if (!before_last_rearm) {
      release_until_ = now + kRelease;
      last_release_end_ = release_until_;
      ++scripted_rearms_;
      advice.hold_disarmed = true;
    }
    advice.hud_text = "re-arming after the robot stopped driving";
    return advice;
  }
  advice.hud_text = keys_held ? "DRIVING STOPPED (commands lost, bumper or e-stop release): let "
                                "go of the drive keys to re-arm, then drive again"
                              : "re-arming: press a drive key once the robot shows IDLE";
  return advice;
}

}  // namespace mostar::ui
