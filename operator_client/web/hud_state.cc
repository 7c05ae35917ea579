#include "operator_client/web/hud_state.h"

#include "operator_client/ui/bumper_display.h"

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
  const ui::BumperView bumpers =
      ui::ViewBumpers(robot.bumpers, robot.last_bumpers_received, steady_now);
  for (const ui::SegmentLook look : bumpers.segments) {
    hud.bumper_segments.push_back(look == ui::SegmentLook::kPressed   ? "pressed"
                                  : look == ui::SegmentLook::kLatched ? "latched"
                                                                      : "idle");
  }
  hud.bumper_alert = bumpers.alert;
  hud.bumper_stale = bumpers.stale;
  hud.bumper_status = bumpers.status;
  hud.footprint_radius_m = inputs.footprint_radius_m;
  hud.pilot = robot.lease ? robot.lease->holder_id
                          : (robot.health ? robot.health->lease_holder : std::string());
  return hud;
}

}  // namespace mostar::web
