// The overlay of one frame from its parts: the sonar sectors on the floor, the scan's AR features
// (walls, rays, circles, vertical lines, laser points), the possible obstacles edge processing
// found (magenta dots at their floor point) and the predicted path while driving. Pure: no GL.
#pragma once

#include <vector>

#include "operator_client/fusion/ar_features.h"
#include "operator_client/fusion/sonar_features.h"
#include "operator_client/fusion/vertex_array.h"
#include "operator_client/render/overlay_geometry.h"
#include "operator_client/vision/nep_classifier.h"

namespace mostar::ui {

// Colour of the possible-obstacle dots.
constexpr fusion::Rgba kPossibleObstacleColor{1.f, 0.f, 1.f, 1.f};

// Appends `sonar` and `features` (when given), `obstacles` and `predicted_path` to `overlay`:
// nothing any of them holds is dropped. The sonar fans come first among the triangles, so that
// the walls are drawn over them.
void AssembleOverlay(const fusion::SonarFeatures* sonar, const fusion::ArFeatures* features,
                     const std::vector<vision::PossibleObstacle>& obstacles,
                     const fusion::VertexArray& predicted_path, render::OverlayGeometry* overlay);

}  // namespace mostar::ui
