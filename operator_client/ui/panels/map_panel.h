// The bird's-eye laser map (top right): the scan's points in their distance colours around the
// robot, forward up, 4 m to each side, rings every 0.5 m. ImGui; render thread.
#pragma once

#include "operator_client/fusion/ar_features.h"

namespace mostar::ui {

void DrawMapPanel(const fusion::ArFeatures& features);

}  // namespace mostar::ui
