#include "operator_client/ui/overlay_assembly.h"

namespace mostar::ui {
namespace {

void Append(const fusion::VertexArray& from, fusion::VertexArray* to) {
  to->positions.insert(to->positions.end(), from.positions.begin(), from.positions.end());
  to->colors.insert(to->colors.end(), from.colors.begin(), from.colors.end());
}

}  // namespace

void AssembleOverlay(const fusion::SonarFeatures* sonar, const fusion::ArFeatures* features,
                     const std::vector<vision::PossibleObstacle>& obstacles,
                     const fusion::VertexArray& predicted_path, render::OverlayGeometry* overlay) {
  if (sonar != nullptr) {
    Append(sonar->fans, &overlay->triangles);
    Append(sonar->outlines, &overlay->lines);
  }
  if (features != nullptr) {
    Append(features->walls, &overlay->triangles);
    Append(features->rays, &overlay->lines);
    Append(features->circles, &overlay->lines);
    Append(features->vertical_lines, &overlay->lines);
    Append(features->laser_points, &overlay->points);
  }
  for (const vision::PossibleObstacle& o : obstacles) {
    overlay->points.Add(static_cast<float>(o.floor_point_laser.x()),
                        static_cast<float>(o.floor_point_laser.y()),
                        static_cast<float>(o.floor_point_laser.z()), kPossibleObstacleColor);
  }
  Append(predicted_path, &overlay->lines);
}

}  // namespace mostar::ui
