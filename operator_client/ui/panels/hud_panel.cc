#include "operator_client/ui/panels/hud_panel.h"

#include <imgui.h>

#include "operator_client/ui/bumper_display.h"

namespace mostar::ui {

void DrawHudPanel(const client::RobotSnapshot& robot, const client::ReceiverStats& video,
                  const HudStatus& status, SteadyTime now) {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("HUD", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                   ImGuiWindowFlags_NoMove);
  if (status.dds_security_off) {
    ImGui::TextColored(ImVec4(1, 0.2f, 0.2f, 1),
                       "DDS SECURITY OFF (--insecure): anyone on the network can watch and drive");
  }
  ImGui::Text("video %.1f fps  %.2f Mbit/s  age %.0f ms", video.pair_rate_hz,
              video.bitrate_bps / 1e6, status.has_pair ? status.display_age_ms : 0.0);
  ImGui::Text("scan %.1f Hz  frame %.1f ms  %s", robot.scan_rate_hz, status.frame_time_ms,
              render::DisplayModeName(status.mode));
  if (video.waiting_for_keyframe) {
    ImGui::TextColored(ImVec4(1, 0.7f, 0.1f, 1),
                       "VIDEO STALE: H.264 data lost, waiting for a keyframe (asked %llu times)",
                       static_cast<unsigned long long>(video.keyframe_requests));
  } else if (video.video_gaps > 0 || video.video_errors > 0) {
    ImGui::Text("H.264: %llu gaps  %llu undecodable  %llu keyframes asked",
                static_cast<unsigned long long>(video.video_gaps),
                static_cast<unsigned long long>(video.video_errors),
                static_cast<unsigned long long>(video.keyframe_requests));
  }
  if (video.broken_images > 0 || video.pairs_dropped > 0) {
    ImGui::Text("dropped pairs %llu  broken JPEG %llu",
                static_cast<unsigned long long>(video.pairs_dropped),
                static_cast<unsigned long long>(video.broken_images));
  }
  if (video.oversized_images > 0 || video.future_dropped > 0 || video.stamp_resyncs > 0) {
    ImGui::TextColored(ImVec4(1, 0.7f, 0.1f, 1),
                       "refused: oversized JPEG %llu  future pairs %llu  (order restarts %llu)",
                       static_cast<unsigned long long>(video.oversized_images),
                       static_cast<unsigned long long>(video.future_dropped),
                       static_cast<unsigned long long>(video.stamp_resyncs));
  }
  if (robot.clock.known) {
    ImGui::Text("clock offset %+.1f ms  rtt %.1f ms",
                ToSeconds(robot.clock.responder_minus_requester) * 1e3,
                ToSeconds(robot.clock.round_trip) * 1e3);
  }
  // Link health: control-path ping loss ("n/a" until pings are answered: never through
  // mostar_relay, docs/operator.md) and the age of the last sample of each stream.
  auto age_ms = [now](SteadyTime t) { return t == SteadyTime() ? -1.0 : ToSeconds(now - t) * 1e3; };
  const std::string loss =
      robot.ping_loss < 0 ? std::string("n/a")
                          : std::to_string(static_cast<int>(robot.ping_loss * 100 + 0.5)) + " %";
  ImGui::Text("link: ping loss %s  last video %.0f  scan %.0f  odom %.0f  health %.0f ms",
              loss.c_str(), status.has_pair ? age_ms(status.pair_received) : -1.0,
              age_ms(robot.last_scan_received), age_ms(robot.last_odometry_received),
              age_ms(robot.last_health_received));
  const uint64_t lost_pairs = video.pairs_dropped + video.unpaired_dropped + video.late_dropped;
  if (lost_pairs > 0) {
    ImGui::Text("video pairs lost here: %llu (replaced %llu, unpaired %llu, late %llu)",
                static_cast<unsigned long long>(lost_pairs),
                static_cast<unsigned long long>(video.pairs_dropped),
                static_cast<unsigned long long>(video.unpaired_dropped),
                static_cast<unsigned long long>(video.late_dropped));
  }
  const bool health_fresh =
      robot.health && now - robot.last_health_received < std::chrono::seconds(3);
  if (!health_fresh) {
    ImGui::TextColored(ImVec4(1, 0.3f, 0.2f, 1), "NO CONTACT WITH THE ROBOT");
  } else {
    const RobotHealth& h = *robot.health;
    const std::string holder = robot.lease ? robot.lease->holder_id : h.lease_holder;
    const bool me = holder == status.client_id;
    ImGui::Text("pilot: %s%s   watchdog: %s", holder.empty() ? "(nobody)" : holder.c_str(),
                me ? " (you)" : "", WatchdogStateName(h.watchdog_state));
    if (h.estop_engaged)
      ImGui::TextColored(ImVec4(1, 0.2f, 0.2f, 1), "EMERGENCY STOP (U releases)");
    for (const DeviceHealth& d : h.devices) {
      if (d.state == DeviceState::kOk) continue;
      ImGui::TextColored(ImVec4(1, 0.7f, 0.1f, 1), "%s %s: %s", d.name.c_str(),
                         DeviceStateName(d.state), d.message.c_str());
    }
  }
  const BumperView bumpers = ViewBumpers(robot.bumpers, robot.last_bumpers_received, now);
  if (!bumpers.status.empty()) {
    const float on = bumpers.flash_on ? 1.f : 0.55f;
    ImGui::TextColored(ImVec4(1, 0.15f * on, 0.15f * on, on), "%s", bumpers.status.c_str());
  }
  if (status.sonar_unseen > 0) {
    ImGui::TextColored(ImVec4(1, 0.3f, 1, 1),
                       "sonar: %zu of %zu echoes where the laser sees nothing", status.sonar_unseen,
                       status.sonar_echoes);
  }
  if (!status.overlay_note.empty()) {
    ImGui::TextColored(ImVec4(1, 0.7f, 0.1f, 1), "%s", status.overlay_note.c_str());
  }
  if (!status.vision_note.empty()) {
    ImGui::TextColored(ImVec4(0.6f, 0.8f, 1, 1), "%s", status.vision_note.c_str());
  }
  if (status.calibration_proposal) {
    ImGui::TextColored(ImVec4(0.4f, 0.9f, 1, 1), "calibration proposal ready: C to review");
  }
  if (status.pending_estop) {
    ImGui::TextColored(ImVec4(1, 0.2f, 0.2f, 1), "e-stop %s sent, not yet confirmed by the robot",
                       *status.pending_estop ? "engage" : "release");
  }
  if (!status.rearm_note.empty()) {
    ImGui::TextColored(ImVec4(1, 0.5f, 0.1f, 1), "%s", status.rearm_note.c_str());
  }
  if (status.pilot) {
    ImGui::Text("drive %s  v %.2f m/s  w %.2f rad/s  scale %.0f%%",
                status.drive.enable ? "ON" : "off", status.drive.linear_mps,
                status.drive.angular_radps, status.drive_scale * 100);
  } else {
    ImGui::Text("observer (no driving)");
  }
  if (!status.status_line.empty()) ImGui::TextUnformatted(status.status_line.c_str());
  ImGui::TextDisabled("F1 help");
  ImGui::End();
}

}  // namespace mostar::ui
