#include "operator_client/ui/panels/calibration_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "common/math/calibration_io.h"

namespace mostar::ui {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// The calibration sliders: a valid edit replaces *c, an invalid one is reported.
void DrawCalibrationSliders(math::LaserCameraCalibration* c, std::string* status_line) {
  math::LaserCameraCalibration edit = *c;
  float focal = static_cast<float>(edit.focal_px);
  float y = static_cast<float>(edit.camera_y_m);
  float tilt_deg = static_cast<float>(edit.tilt_rad * kRadToDeg);
  float z = static_cast<float>(edit.camera_z_m);
  float x = static_cast<float>(edit.camera_x_m);
  float pan_deg = static_cast<float>(edit.pan_rad * kRadToDeg);
  float roll_deg = static_cast<float>(edit.roll_rad * kRadToDeg);
  float baseline = static_cast<float>(edit.baseline_m());
  float laser_h = static_cast<float>(edit.laser_height_m);
  bool changed = false;
  changed |= ImGui::SliderFloat("1 focal [px]", &focal, 150, 2000, "%.1f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Scales the overlay: match far walls first.");
  changed |= ImGui::SliderFloat("2 camera y [m]", &y, -0.5f, 2.0f, "%.3f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Height above the scan plane: moves floor rays.");
  changed |= ImGui::SliderFloat("2 tilt [deg]", &tilt_deg, -45, 45, "%.2f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Down is positive: moves the overlay vertically.");
  changed |= ImGui::SliderFloat("3 camera z [m]", &z, -1.0f, 1.0f, "%.3f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Ahead of the laser: matters on near objects.");
  changed |= ImGui::SliderFloat("4 camera x [m]", &x, -0.5f, 0.5f, "%.3f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Right of the laser: shifts sideways.");
  changed |= ImGui::SliderFloat("pan [deg]", &pan_deg, -20, 20, "%.2f");
  changed |= ImGui::SliderFloat("roll [deg]", &roll_deg, -10, 10, "%.2f");
  changed |= ImGui::SliderFloat("baseline [m]", &baseline, 0.0f, 0.3f, "%.3f");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Distance between the eyes (5-20 cm).");
  changed |= ImGui::SliderFloat("laser height [m]", &laser_h, 0.05f, 1.5f, "%.3f");
  if (!changed) return;
  edit.focal_px = focal;
  edit.camera_y_m = y;
  edit.tilt_rad = tilt_deg / kRadToDeg;
  edit.camera_z_m = z;
  edit.camera_x_m = x;
  edit.pan_rad = pan_deg / kRadToDeg;
  edit.roll_rad = roll_deg / kRadToDeg;
  edit.left_eye_x_offset_m = -baseline / 2;
  edit.right_eye_x_offset_m = baseline / 2;
  edit.laser_height_m = laser_h;
  std::string error;
  if (edit.IsValid(&error)) {
    *c = edit;
  } else {
    *status_line = "calibration: " + error;
  }
}

// Save/Load write and read the calibration with the stereo alignment in one profile.
void DrawProfileButtons(const std::string& profile_path, const CalibrationPanelTargets& edit) {
  const std::string path = profile_path.empty() ? "calibration_profile.pbtxt" : profile_path;
  std::string* status_line = edit.status_line;
  if (ImGui::Button("Save")) {
    std::string error;
    const math::StereoAlignmentProfile alignment =
        render::ToProfile(*edit.alignment_model, *edit.left_alignment, *edit.right_alignment);
    *status_line =
        math::SaveCalibrationProfile(path, *edit.calibration, alignment, "operator", &error)
            ? "saved " + path
            : "save failed: " + error;
  }
  ImGui::SameLine();
  if (ImGui::Button("Load")) {
    std::string error;
    math::LaserCameraCalibration loaded;
    math::StereoAlignmentProfile alignment;
    if (math::LoadCalibrationProfile(path, &loaded, &alignment, &error)) {
      *edit.calibration = loaded;
      render::FromProfile(alignment, edit.alignment_model, edit.left_alignment,
                          edit.right_alignment);
      *status_line = "loaded " + path;
    } else {
      *status_line = "load failed: " + error;
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("Reset")) *edit.calibration = math::LaserCameraCalibration{};
}

void DrawArSwitches(fusion::ArFeatureOptions* ar) {
  ImGui::Checkbox("walls", &ar->walls_enabled);
  ImGui::SameLine();
  ImGui::Checkbox("rays", &ar->rays_enabled);
  ImGui::SameLine();
  ImGui::Checkbox("lines", &ar->vertical_lines_enabled);
  ImGui::SameLine();
  ImGui::Checkbox("circles", &ar->circles_enabled);
  ImGui::SameLine();
  ImGui::Checkbox("labels", &ar->labels_enabled);
  ImGui::SliderFloat("red below [m]", &ar->min_distance_m, 0.1f, 3.0f, "%.2f");
  ImGui::SliderFloat("green above [m]", &ar->max_distance_m, ar->min_distance_m + 0.1f, 8.0f,
                     "%.2f");
  ImGui::SliderFloat("slopeTh", &ar->segmentation.slope_threshold, 0.005f, 0.5f, "%.3f");
}

void DrawStereoAlignment(const CalibrationPanelTargets& edit,
                         const std::optional<StereoOffsetHint>& hint) {
  render::EyeAlignment* left = edit.left_alignment;
  render::EyeAlignment* right = edit.right_alignment;
  ImGui::TextUnformatted("Right eye image offset (px) and rotation:");
  int model = *edit.alignment_model == render::AlignmentModel::kPerEyeIntrinsics ? 1 : 0;
  const char* models[] = {"shared parameters (thesis)", "per-eye intrinsics"};
  if (ImGui::Combo("model", &model, models, 2)) {
    *edit.alignment_model = model == 1 ? render::AlignmentModel::kPerEyeIntrinsics
                                       : render::AlignmentModel::kSharedModel;
  }
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip(
        "Shared: the calibration describes the aligned images; the offset moves the right "
        "image under its overlay. Per-eye: each eye's intrinsics describe its own camera; the "
        "overlay moves with its image.");
  }
  float dx = right->offset_x_px;
  float dy = right->offset_y_px;
  ImGui::SliderFloat("dx", &dx, -40, 40, "%.1f");
  ImGui::SliderFloat("dy", &dy, -40, 40, "%.1f");
  float rotation_deg = static_cast<float>(right->rotation_rad * kRadToDeg);
  if (ImGui::SliderFloat("rotation [deg]", &rotation_deg, -5, 5, "%.2f")) {
    right->rotation_rad = static_cast<float>(rotation_deg / kRadToDeg);
  }
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip(
        "Turns the right image about its principal point: a right camera rolled by r is "
        "aligned by -r.");
  }
  if (hint) {
    ImGui::Text("NESC: right image %.1f px %s (spread %.1f px, %d edges): dy %.1f",
                std::abs(hint->residual_px), hint->residual_px > 0 ? "low" : "high",
                hint->spread_px, hint->samples, hint->suggested_right_offset_y_px);
    ImGui::SameLine();
    if (ImGui::Button("Apply")) dy = hint->suggested_right_offset_y_px;
  } else {
    ImGui::TextDisabled("NESC: no vertical offset measured yet (edges on, both eyes)");
  }
  // Crop the borders without correspondence in both eyes.
  render::CropForRightOffset(dx, dy, left, right);
}

// A few words for the section's title: off, no proposal yet, or what the proposal is.
std::string SelfCalibrationState(const ConsoleSelfCalibration& self) {
  if (!self.enabled()) return "off";
  const std::shared_ptr<const calibration::FitResult> shown = self.proposal();
  if (!shown) return "collecting";
  if (!shown->ok) return "no proposal";
  return shown->trustworthy ? "proposal ready" : "proposal not trustworthy";
}

// One row of the proposal table: the parameter, its current and its proposed value.
void ProposalRow(const char* name, const char* format, double current, double proposed) {
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(name);
  ImGui::TableNextColumn();
  ImGui::Text(format, current);
  ImGui::TableNextColumn();
  ImGui::Text(format, proposed);
}

// The self-calibration's proposal (issue 17): current vs proposed values, the reprojection
// error of both over the proposal's inliers, whether it can be trusted, Apply and Reject.
void DrawSelfCalibration(ConsoleSelfCalibration* self, math::LaserCameraCalibration* live,
                         std::string* status_line) {
  if (!self->enabled()) {
    ImGui::TextDisabled("off in the client configuration (self_calibration { enabled: false })");
    return;
  }
  ImGui::Text("%zu agreeing NEPs in the window", self->window_points());
  const std::shared_ptr<const calibration::FitResult> shown = self->proposal();
  if (!shown) {
    ImGui::TextDisabled("no proposal yet: edges on, drive past walls");
    return;
  }
  if (!shown->ok) {
    ImGui::TextDisabled("no proposal: %s", shown->reason.c_str());
    return;
  }
  const math::LaserCameraCalibration& a = shown->start;
  const math::LaserCameraCalibration& b = shown->proposal;
  if (ImGui::BeginTable("self_calibration", 3, ImGuiTableFlags_BordersInnerV)) {
    ImGui::TableSetupColumn("");
    ImGui::TableSetupColumn("current");
    ImGui::TableSetupColumn("proposed");
    ImGui::TableHeadersRow();
    ProposalRow("focal [px]", "%.1f", a.focal_px, b.focal_px);
    ProposalRow("camera x [m]", "%.4f", a.camera_x_m, b.camera_x_m);
    ProposalRow("camera y [m]", "%.4f", a.camera_y_m, b.camera_y_m);
    ProposalRow("camera z [m]", "%.4f", a.camera_z_m, b.camera_z_m);
    ProposalRow("tilt [deg]", "%.2f", a.tilt_rad * kRadToDeg, b.tilt_rad * kRadToDeg);
    ProposalRow("pan [deg]", "%.2f", a.pan_rad * kRadToDeg, b.pan_rad * kRadToDeg);
    ProposalRow("roll [deg]", "%.2f", a.roll_rad * kRadToDeg, b.roll_rad * kRadToDeg);
    ProposalRow("error p50 [px]", "%.2f", shown->before.p50_px, shown->after.p50_px);
    ProposalRow("error p95 [px]", "%.2f", shown->before.p95_px, shown->after.p95_px);
    ImGui::EndTable();
  }
  ImGui::Text("%zu of %zu points fit", shown->inliers, shown->points);
  if (shown->trustworthy) {
    ImGui::TextUnformatted("trustworthy");
  } else {
    ImGui::TextColored(ImVec4(1.f, 0.7f, 0.2f, 1.f), "not trustworthy: %s", shown->reason.c_str());
  }
  ImGui::BeginDisabled(!shown->trustworthy);
  if (ImGui::Button("Apply proposal")) self->Apply(live, status_line);
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (ImGui::Button("Reject")) self->Reject();
}

void DrawDisplayMode(render::DisplayMode* mode) {
  int mode_index = 0;
  const char* names[render::kDisplayModeCount];
  for (int i = 0; i < render::kDisplayModeCount; ++i) {
    if (render::kDisplayModes[i] == *mode) mode_index = i;
    names[i] = render::DisplayModeName(render::kDisplayModes[i]);
  }
  if (ImGui::Combo("display", &mode_index, names, render::kDisplayModeCount)) {
    *mode = render::kDisplayModes[mode_index];
  }
}

}  // namespace

void DrawCalibrationPanel(const std::string& profile_path, const CalibrationPanelTargets& edit,
                          const std::optional<StereoOffsetHint>& hint) {
  // Below the HUD; never taller than the window (it scrolls), so that in a 640 x 480 window the
  // stereo alignment and NESC's hint at the bottom stay reachable.
  const ImGuiIO& io = ImGui::GetIO();
  const float top = std::min(190.f, io.DisplaySize.y * 0.25f);
  ImGui::SetNextWindowPos(ImVec2(8, top), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(430, 0), ImGuiCond_FirstUseEver);  // height: fit, capped
  ImGui::SetNextWindowSizeConstraints(
      ImVec2(280, 120), ImVec2(io.DisplaySize.x, std::max(120.f, io.DisplaySize.y - top - 8)));
  ImGui::Begin("Calibration", edit.open);
  constexpr ImGuiTreeNodeFlags kOpen = ImGuiTreeNodeFlags_DefaultOpen;
  if (ImGui::CollapsingHeader("Laser-camera calibration", kOpen)) {
    ImGui::TextWrapped(
        "Order: 1 focal on far objects, 2 y and tilt on the floor, 3 z on near objects, "
        "4 x last. Rays and lines are shown while this panel is open.");
    DrawCalibrationSliders(edit.calibration, edit.status_line);
    DrawProfileButtons(profile_path, edit);
  }
  if (edit.self_calibration != nullptr) {
    // The state in the title, so that a collapsed section still tells of a proposal.
    const std::string title =
        "Self-calibration: " + SelfCalibrationState(*edit.self_calibration) + "###self_calibration";
    if (ImGui::CollapsingHeader(title.c_str(), kOpen)) {
      DrawSelfCalibration(edit.self_calibration, edit.calibration, edit.status_line);
    }
  }
  if (ImGui::CollapsingHeader("AR features", kOpen)) DrawArSwitches(edit.ar);
  if (ImGui::CollapsingHeader("Stereo alignment and display", kOpen)) {
    DrawStereoAlignment(edit, hint);
    DrawDisplayMode(edit.mode);
  }
  ImGui::End();
}

}  // namespace mostar::ui
