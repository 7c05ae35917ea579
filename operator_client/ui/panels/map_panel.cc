#include "operator_client/ui/panels/map_panel.h"

#include <imgui.h>

#include <cmath>

#include "operator_client/ui/panels/im_color.h"

namespace mostar::ui {

void DrawMapPanel(const fusion::ArFeatures& features) {
  const float size = 220.f;
  const float range_m = 4.f;
  ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - size - 24, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.55f);
  ImGui::Begin("Laser map", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                   ImGuiWindowFlags_NoMove);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::Dummy(ImVec2(size, size));
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float scale = size / (2 * range_m);
  // Robot at the bottom centre, forward up; laser x forward -> screen up, y left -> screen left.
  const ImVec2 robot_px(origin.x + size / 2, origin.y + size - 10);
  auto to_screen = [&](float x, float y) {
    return ImVec2(robot_px.x - y * scale, robot_px.y - x * scale);
  };
  for (float r = 0.5f; r <= 2 * range_m; r += 0.5f) {
    draw->AddCircle(robot_px, r * scale, IM_COL32(255, 255, 255, r == std::floor(r) ? 70 : 35), 64);
  }
  for (const fusion::ScanPointLabel& p : features.points) {
    if (!p.valid) continue;
    const ImVec2 s = to_screen(p.x_m, p.y_m);
    if (s.x < origin.x || s.x > origin.x + size || s.y < origin.y || s.y > origin.y + size) {
      continue;
    }
    draw->AddRectFilled(ImVec2(s.x - 1.5f, s.y - 1.5f), ImVec2(s.x + 1.5f, s.y + 1.5f),
                        ToImColor(p.color));
  }
  draw->AddTriangleFilled(ImVec2(robot_px.x, robot_px.y - 9),
                          ImVec2(robot_px.x - 6, robot_px.y + 4),
                          ImVec2(robot_px.x + 6, robot_px.y + 4), IM_COL32(80, 160, 255, 255));
  ImGui::End();
}

}  // namespace mostar::ui
