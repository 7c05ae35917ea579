#include "operator_client/ui/panels/edge_view_panel.h"

#include <imgui.h>

#include <cstdint>

namespace mostar::ui {

namespace {

ImTextureID ImTexture(const render::Texture& texture) {
  return reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture.id()));
}

}  // namespace

std::optional<vision::VisionOptions> EdgeViewPanel::Draw(const vision::VisionResult* result,
                                                         vision::VisionOptions* options, bool* open,
                                                         bool* vision_enabled) {
  ImGui::SetNextWindowPos(ImVec2(20, 60), ImGuiCond_FirstUseEver);
  ImGui::Begin("Edges (thesis fig. 29)", open, ImGuiWindowFlags_AlwaysAutoResize);
  vision::EdgeDetectorOptions& e = options->edges;
  bool changed = false;
  changed |= ImGui::SliderInt("lowTh", &e.low_threshold, 0, 254);
  changed |= ImGui::SliderInt("highTh", &e.high_threshold, 1, 255);
  float th1 = static_cast<float>(e.canny_threshold1);
  float th2 = static_cast<float>(e.canny_threshold2);
  changed |= ImGui::SliderFloat("th1", &th1, 0, 500, "%.0f");
  changed |= ImGui::SliderFloat("th2", &th2, 0, 800, "%.0f");
  float edge_th = static_cast<float>(options->classifier.edge_threshold_m);
  changed |= ImGui::SliderFloat("edgeTh [m]", &edge_th, 0.02f, 0.5f, "%.2f");
  ImGui::Checkbox("edge processing (E)", vision_enabled);
  std::optional<vision::VisionOptions> next;
  if (changed) {
    next = *options;
    next->edges.canny_threshold1 = th1;
    next->edges.canny_threshold2 = th2;
    next->classifier.edge_threshold_m = edge_th;
  }
  if (result && !result->left_edges.edges.empty()) {
    grey_.Upload(result->left_edges.stretched_grey);
    edges_.Upload(result->left_edges.edges);
    const ImVec2 size(320, 240);
    ImGui::Image(ImTexture(grey_), size);
    ImGui::SameLine();
    ImGui::Image(ImTexture(edges_), size);
    const auto& c = result->classification;
    ImGui::Text("NEPs: %d corrected, %d possible obstacles; %.1f ms", c.corrected, c.nearer,
                ToSeconds(result->processing_time) * 1e3);
  } else {
    ImGui::TextUnformatted("no edge result yet");
  }
  ImGui::End();
  return next;
}

}  // namespace mostar::ui
