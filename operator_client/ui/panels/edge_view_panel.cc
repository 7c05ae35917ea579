#include "operator_client/ui/panels/edge_view_panel.h"

#include <imgui.h>

#include <cstdint>

namespace mostar::ui {

namespace {

ImTextureID ImTexture(const render::Texture& texture) {
  return reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture.id()));
}

}  // namespace

std::optional<VisionSettings> EdgeViewPanel::Draw(const vision::VisionResult* result,
                                                  const VisionSettings& settings,
                                                  const std::string& settings_path, bool* open,
                                                  bool* vision_enabled, std::string* status_line) {
  ImGui::SetNextWindowPos(ImVec2(20, 60), ImGuiCond_FirstUseEver);
  ImGui::Begin("Edges (thesis fig. 29)", open, ImGuiWindowFlags_AlwaysAutoResize);
  VisionSettings edit = settings;
  vision::VisionOptions options = settings.options();
  vision::EdgeDetectorOptions& e = options.edges;
  bool changed = false;
  changed |= ImGui::SliderInt("lowTh", &e.low_threshold, 0, 254);
  changed |= ImGui::SliderInt("highTh", &e.high_threshold, 1, 255);
  float th1 = static_cast<float>(e.canny_threshold1);
  float th2 = static_cast<float>(e.canny_threshold2);
  changed |= ImGui::SliderFloat("th1", &th1, 0, 500, "%.0f");
  changed |= ImGui::SliderFloat("th2", &th2, 0, 800, "%.0f");
  e.canny_threshold1 = th1;
  e.canny_threshold2 = th2;
  changed |= ImGui::Checkbox("colour edges", &e.colour_edges);
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip("Also edges of colour (R - G): bases as grey as the floor");
  }
  std::string error;
  bool ok = true;
  if (changed) ok = edit.Set(options, &error);
  float edge_th = static_cast<float>(settings.options().classifier.edge_threshold_m);
  if (ImGui::SliderFloat("edgeTh [m]", &edge_th, 0.02f, 0.5f, "%.3f")) {
    changed = true;
    ok = ok && edit.SetEdgeThreshold(edge_th, &error);
  }
  float stereo_th = static_cast<float>(settings.options().nesc.stereo_threshold_m);
  if (ImGui::SliderFloat("stereoTh [m]", &stereo_th, 0.01f, 0.5f, "%.3f")) {
    changed = true;
    ok = ok && edit.SetStereoThreshold(stereo_th, &error);
  }
  bool follows = settings.stereo_follows_edge();
  if (ImGui::Checkbox("stereoTh = edgeTh / 2 (thesis)", &follows) && follows) {
    changed = true;
    ok = ok && edit.FollowEdgeThreshold(&error);
  }
  if (ImGui::Button("Save")) {
    *status_line =
        settings.Save(settings_path, &error) ? "saved " + settings_path : "save failed: " + error;
  }
  ImGui::SameLine();
  if (ImGui::Button("Load")) {
    changed = true;
    ok = edit.Load(settings_path, &error);
    if (ok) *status_line = "loaded " + settings_path;
  }
  ImGui::SameLine();
  ImGui::TextDisabled("%s", settings_path.c_str());
  ImGui::Checkbox("edge processing (E)", vision_enabled);
  int eye = eye_ == Eye::kLeft ? 0 : 1;
  ImGui::RadioButton("left eye", &eye, 0);
  ImGui::SameLine();
  ImGui::RadioButton("right eye", &eye, 1);
  eye_ = eye == 0 ? Eye::kLeft : Eye::kRight;

  const vision::EdgeImages* images = nullptr;
  if (result) images = eye_ == Eye::kLeft ? &result->left_edges : &result->right_edges;
  if (images && !images->edges.empty()) {
    grey_.Upload(images->stretched_grey);
    edges_.Upload(images->edges);
    const ImVec2 size(320, 240);
    ImGui::Image(ImTexture(grey_), size);
    ImGui::SameLine();
    ImGui::Image(ImTexture(edges_), size);
    const auto& c = result->classification;
    ImGui::Text("NEPs: %d corrected, %d possible obstacles; %.1f ms", c.corrected, c.nearer,
                ToSeconds(result->processing_time) * 1e3);
  } else {
    ImGui::TextUnformatted(eye_ == Eye::kRight ? "no right-eye edges (monoscopic or none yet)"
                                               : "no edge result yet");
  }
  ImGui::End();
  if (!changed) return std::nullopt;
  if (!ok) {
    *status_line = "edges: " + error;
    return std::nullopt;
  }
  return edit;
}

}  // namespace mostar::ui
