#include "operator_client/ui/panels/map_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "operator_client/ui/panels/im_color.h"

namespace mostar::ui {
namespace {

constexpr float kPi = 3.14159265f;

ImU32 SegmentColor(SegmentLook look, bool flash_on) {
  switch (look) {
    case SegmentLook::kPressed:
      return flash_on ? IM_COL32(255, 40, 40, 255) : IM_COL32(120, 20, 20, 255);
    case SegmentLook::kLatched:
      return IM_COL32(255, 40, 40, 255);
    case SegmentLook::kIdle:
      break;
  }
  return IM_COL32(80, 160, 255, 160);
}

}  // namespace

void DrawMapPanel(const fusion::ArFeatures& features, const fusion::SonarFeatures& sonar,
                  const BumperView& bumpers, float footprint_radius_m) {
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
  draw->PushClipRect(origin, ImVec2(origin.x + size, origin.y + size), true);
  const float scale = size / (2 * range_m);
  // The robot 40 px above the bottom centre (its rear bumpers stay visible), forward up; laser
  // x forward -> screen up, y left -> screen left.
  const ImVec2 robot_px(origin.x + size / 2, origin.y + size - 40);
  auto to_screen = [&](float x, float y) {
    return ImVec2(robot_px.x - y * scale, robot_px.y - x * scale);
  };
  for (float r = 0.5f; r <= 2 * range_m; r += 0.5f) {
    draw->AddCircle(robot_px, r * scale, IM_COL32(255, 255, 255, r == std::floor(r) ? 70 : 35), 64);
  }
  // Sonar fans (triangles) under the laser points, then the outlines of the unseen ones.
  const std::vector<float>& fp = sonar.fans.positions;
  const std::vector<float>& fc = sonar.fans.colors;
  for (size_t v = 0; v + 2 < sonar.fans.vertex_count(); v += 3) {
    const fusion::Rgba c{fc[4 * v], fc[4 * v + 1], fc[4 * v + 2], fc[4 * v + 3]};
    draw->AddTriangleFilled(to_screen(fp[3 * v], fp[3 * v + 1]),
                            to_screen(fp[3 * v + 3], fp[3 * v + 4]),
                            to_screen(fp[3 * v + 6], fp[3 * v + 7]), ToImColor(c));
  }
  const std::vector<float>& op = sonar.outlines.positions;
  for (size_t v = 0; v + 1 < sonar.outlines.vertex_count(); v += 2) {
    draw->AddLine(to_screen(op[3 * v], op[3 * v + 1]), to_screen(op[3 * v + 3], op[3 * v + 4]),
                  IM_COL32(255, 60, 255, 255), 1.5f);
  }
  for (const fusion::ScanPointLabel& p : features.points) {
    if (!p.valid) continue;
    const ImVec2 s = to_screen(p.x_m, p.y_m);
    draw->AddRectFilled(ImVec2(s.x - 1.5f, s.y - 1.5f), ImVec2(s.x + 1.5f, s.y + 1.5f),
                        ToImColor(p.color));
  }
  // The robot's outline: one arc per bumper segment (segment i centred at i x 360/N degrees
  // counter-clockwise from ahead), or a plain circle when the robot has no bumper belt.
  const float radius_px = std::max(4.f, footprint_radius_m * scale);
  const int count = static_cast<int>(bumpers.segments.size());
  if (count == 0) {
    draw->AddCircle(robot_px, radius_px, IM_COL32(80, 160, 255, 160), 32, 1.5f);
  }
  for (int i = 0; i < count; ++i) {
    const float width = 2 * kPi / count;
    const float centre = i * width;  // counter-clockwise from ahead (screen up)
    const int steps = 6;
    ImVec2 points[steps + 1];
    for (int k = 0; k <= steps; ++k) {
      // Leave a small gap between segments so that each reads as its own switch.
      const float a = centre - 0.45f * width + 0.9f * width * k / steps;
      points[k] = to_screen(footprint_radius_m * std::cos(a), footprint_radius_m * std::sin(a));
    }
    const bool alert = bumpers.segments[i] != SegmentLook::kIdle;
    draw->AddPolyline(points, steps + 1, SegmentColor(bumpers.segments[i], bumpers.flash_on), 0,
                      alert ? 4.f : 2.f);
  }
  draw->AddTriangleFilled(ImVec2(robot_px.x, robot_px.y - 9),
                          ImVec2(robot_px.x - 6, robot_px.y + 4),
                          ImVec2(robot_px.x + 6, robot_px.y + 4), IM_COL32(80, 160, 255, 255));
  draw->PopClipRect();
  ImGui::End();
}

}  // namespace mostar::ui
