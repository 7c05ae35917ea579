// The bird's-eye map (top right): the scan's points in their distance colours around the
// robot, forward up, 4 m to each side, rings every 0.5 m; the sonar sectors (outlined in
// magenta where the laser sees nothing) and the robot's outline with its bumper segments
// (flashing red while pressed, steady red while latched). ImGui; render thread.
#pragma once

#include "operator_client/fusion/ar_features.h"
#include "operator_client/fusion/sonar_features.h"
#include "operator_client/ui/bumper_display.h"

namespace mostar::ui {

// `footprint_radius_m`: radius of the robot outline the bumper segments are drawn on (> 0).
void DrawMapPanel(const fusion::ArFeatures& features, const fusion::SonarFeatures& sonar,
                  const BumperView& bumpers, float footprint_radius_m);

}  // namespace mostar::ui
