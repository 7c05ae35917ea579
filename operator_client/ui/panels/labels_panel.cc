#include "operator_client/ui/panels/labels_panel.h"

#include <imgui.h>

#include <vector>

#include "operator_client/render/eye_viewports.h"
#include "operator_client/ui/panels/im_color.h"

namespace mostar::ui {

void DrawLabelsPanel(const fusion::ArFeatures& features, const math::CameraModel& left_display,
                     const math::CameraModel& right_display, render::DisplayMode mode,
                     int framebuffer_w, int framebuffer_h) {
  ImDrawList* draw = ImGui::GetForegroundDrawList();
  const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
  const std::vector<render::EyeViewport> viewports =
      render::EyeViewports(mode, framebuffer_w, framebuffer_h);
  for (size_t i = 0; i < viewports.size(); ++i) {
    const render::EyeViewport& r = viewports[i];
    if (i > 0 && r.SameRect(viewports[0])) continue;  // one set of labels per rectangle
    const math::CameraModel& model = r.eye == math::Eye::kLeft ? left_display : right_display;
    const float x0 = static_cast<float>(r.x_px);
    const float y0 = static_cast<float>(r.y_px);
    const float w = static_cast<float>(r.width_px);
    const float h = static_cast<float>(r.height_px);
    for (const fusion::DistanceLabel& label : features.labels) {
      const auto px = model.ProjectUndistorted(
          Eigen::Vector3d(label.anchor_x_m, label.anchor_y_m, label.anchor_z_m));
      if (!px || !model.IsInImage(*px)) continue;
      const float x = (x0 + static_cast<float>((*px)(0) + 0.5) * w / model.width_px()) / scale.x;
      const float y = (y0 + static_cast<float>((*px)(1) + 0.5) * h / model.height_px()) / scale.y;
      const ImVec2 size = ImGui::CalcTextSize(label.text.c_str());
      const ImVec2 top_left(x - size.x / 2 - 4, y - size.y - 4);
      draw->AddRectFilled(top_left, ImVec2(x + size.x / 2 + 4, y), IM_COL32(0, 0, 0, 170), 4);
      draw->AddText(ImVec2(x - size.x / 2, y - size.y - 2), ToImColor(label.color),
                    label.text.c_str());
    }
  }
}

}  // namespace mostar::ui
