#include "operator_client/web/hud_state.h"

namespace mostar::web {

HudState MakeHud(const client::RobotSnapshot& robot, const HudInputs& inputs, Time now,
                 SteadyTime steady_now) {
  HudState hud;
  auto age_ms = [steady_now](SteadyTime t) {
    return t == SteadyTime() ? -1.0 : ToSeconds(steady_now - t) * 1e3;
  };
  auto fresh = [steady_now](SteadyTime t) {
    return t != SteadyTime() && steady_now - t < kStaleAfter;
  };
  if (inputs.newest_pair_stamp) hud.frame_age_ms = ToSeconds(now - *inputs.newest_pair_stamp) * 1e3;
  hud.scan_age_ms = age_ms(robot.last_scan_received);
  hud.health_age_ms = age_ms(robot.last_health_received);
  hud.video_fps = inputs.video_fps;
  hud.scan_rate_hz = robot.scan_rate_hz;
  hud.browsers = inputs.browsers;
  hud.dds_security_off = inputs.dds_security_off;
  const bool video_fresh = inputs.newest_pair_received && fresh(*inputs.newest_pair_received);
  if (!robot.health || !fresh(robot.last_health_received)) {
    hud.link = "no contact";
  } else if (!video_fresh) {
    hud.link = "no video";
  } else if (!fresh(robot.last_scan_received)) {
    hud.link = "no scans";
  } else {
    hud.link = "ok";
  }
  if (robot.health) {
    const RobotHealth& h = *robot.health;
    hud.robot_id = h.robot_id;
    hud.watchdog = WatchdogStateName(h.watchdog_state);
    hud.estop_engaged = h.estop_engaged;
    for (const DeviceHealth& d : h.devices) {
      if (d.state == DeviceState::kOk) continue;
      hud.warnings.push_back(d.name + " " + DeviceStateName(d.state) + ": " + d.message);
    }
  }
  hud.pilot = robot.lease ? robot.lease->holder_id
                          : (robot.health ? robot.health->lease_holder : std::string());
  return hud;
}

}  // namespace mostar::web
