// Colour conversion shared by the panels. ImGui.
#pragma once

#include <imgui.h>

#include "operator_client/fusion/vertex_array.h"

namespace mostar::ui {

inline ImU32 ToImColor(const fusion::Rgba& c, float alpha = 1.f) {
  return ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, c.a * alpha));
}

}  // namespace mostar::ui
