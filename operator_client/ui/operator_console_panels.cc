// The console's ImGui panels over the composed frame: labels, HUD, map, calibration, edge
// view, latency and help (OperatorConsole::DrawPanels; the rest of the class is in
// operator_console.cc).
#include "operator_client/ui/bumper_display.h"
#include "operator_client/ui/operator_console.h"
#include "operator_client/ui/panels/calibration_panel.h"
#include "operator_client/ui/panels/help_panel.h"
#include "operator_client/ui/panels/hud_panel.h"
#include "operator_client/ui/panels/labels_panel.h"
#include "operator_client/ui/panels/latency_panel.h"
#include "operator_client/ui/panels/map_panel.h"

namespace mostar::ui {

void OperatorConsole::DrawPanels(const client::RobotSnapshot& robot,
                                 const fusion::ArFeatures& features,
                                 const fusion::SonarFeatures& sonar,
                                 const std::optional<client::DecodedStereoPair>& pair, int fb_w,
                                 int fb_h) {
  if (options_.ar.labels_enabled) {
    DrawLabelsPanel(features, geometry_.eye(0).display, geometry_.eye(1).display, options_.mode,
                    fb_w, fb_h);
  }
  if (options_.show_hud) {
    HudStatus hud;
    hud.has_pair = pair.has_value();
    if (pair) hud.pair_received = pair->received;
    hud.display_age_ms = shown_.last_display_age_ms();
    hud.frame_time_ms = frame_time_ms_;
    hud.mode = options_.mode;
    hud.client_id = options_.client_id;
    hud.pilot = options_.pilot;
    hud.dds_security_off = options_.dds_security_off;
    hud.drive = drive_;
    hud.drive_scale = mapper_.scale();
    hud.status_line = status_line_;
    hud.pending_estop = commands_->pending_estop();
    hud.rearm_note = rearm_.hud_text;
    hud.sonar_echoes = sonar.echoes;
    hud.sonar_unseen = sonar.unseen;
    hud.overlay_note = MotionOverlayNote(motion_);
    if (options_.vision_enabled) hud.vision_note = ResultNote(vision_->picker().result_state());
    hud.calibration_proposal = !options_.show_calibration_panel && selfcal_.trustworthy_proposal();
    DrawHudPanel(robot, video_->Stats(), hud, clock_->SteadyNow());
  }
  if (options_.show_map) {
    DrawMapPanel(features, sonar,
                 ViewBumpers(robot.bumpers, robot.last_bumpers_received, clock_->SteadyNow()),
                 options_.path.half_width_m);
  }
  if (options_.show_calibration_panel) {
    DrawCalibrationPanel(options_.calibration_path,
                         {&options_.show_calibration_panel, &options_.calibration, &options_.ar,
                          &options_.left_alignment, &options_.right_alignment,
                          &options_.alignment_model, &options_.mode, &status_line_, &selfcal_},
                         vision_->OffsetHint([this](double residual_px) {
                           return SuggestedRightOffsetInProfile(geometry_, options_.left_alignment,
                                                                image_scale_, residual_px);
                         }));
  }
  if (show_edge_view_) {
    const std::optional<VisionSettings> next =
        edge_view_.Draw(vision_->picker().shown_result().get(), vision_->settings(),
                        VisionSettingsPath(options_.calibration_path), &show_edge_view_,
                        &options_.vision_enabled, &status_line_);
    std::string error;
    if (next && vision_->ApplySettings(*next, &error)) options_.vision = next->options();
    if (next && !error.empty()) status_line_ = "edges: " + error;
  }
  if (show_latency_) DrawLatencyPanel(latency_, frame_parts_.Rows(), &show_latency_);
  if (show_help_) DrawHelpPanel(&show_help_);
}

}  // namespace mostar::ui
