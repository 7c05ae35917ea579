#include "operator_client/web/frame_composer.h"

#include <algorithm>

#include "common/check/check.h"
#include "operator_client/render/overlay_geometry.h"
#include "operator_client/ui/overlay_assembly.h"
#include "operator_client/web/web_messages.h"

namespace mostar::web {

bool ComposerOptions::IsValid(std::string* error) const {
  if (!calibration.IsValid(error)) return false;
  if (!ar.IsValid(error)) return false;
  if (!sonar.IsValid(error)) return false;
  if (!motion.IsValid(error)) return false;
  render::StereoGeometry geometry;
  std::string why;
  if (!geometry.Update(calibration, calibration, alignment_model, left_alignment, right_alignment,
                       &why) &&
      !geometry.ready()) {
    *error = why;
    return false;
  }
  return true;
}

FrameComposer::FrameComposer(const ComposerOptions& options)
    : options_(options),
      builders_(ui::OverlayArOptions(options.ar, options.calibration.laser_height_m, false)) {
  std::string error;
  MOSTAR_CHECK(options_.IsValid(&error)) << error;
  RefreshGeometry();
}

void FrameComposer::RefreshGeometry() {
  std::string error;
  geometry_.Update(options_.calibration, options_.calibration, options_.alignment_model,
                   options_.left_alignment, options_.right_alignment, &error);
  MOSTAR_CHECK(geometry_.ready()) << error;  // the calibration was checked valid
  left_model_ = std::make_shared<const math::CameraModel>(geometry_.eye(0).image);
  right_model_ = std::make_shared<const math::CameraModel>(geometry_.eye(1).image);
}

std::vector<bool> FrameComposer::PotentialOutliers(const LaserScan& scan) {
  std::string error;
  return ui::PotentialOutliers(
      builders_.For(ui::OverlayArOptions(options_.ar, options_.calibration.laser_height_m, false),
                    &error),
      scan);
}

void FrameComposer::SetRobotIntrinsics(const std::optional<CameraIntrinsicsInfo>& left,
                                       std::string* message) {
  message->clear();
  if (!options_.intrinsics_from_robot) return;
  const ui::IntrinsicsAdopter::Result result = intrinsics_.Apply(left, &options_.calibration);
  if (result.outcome == ui::IntrinsicsAdopter::Outcome::kRefused) *message = result.message;
  if (result.outcome == ui::IntrinsicsAdopter::Outcome::kAdopted) RefreshGeometry();
}

ComposedFrame FrameComposer::Compose(const CompressedStereoPair& pair, const FrameInputs& inputs,
                                     uint32_t sequence, bool both_eyes) {
  static const std::vector<vision::PossibleObstacle> kNone;
  const bool edges = inputs.edges && inputs.edges->ok;
  const std::vector<vision::PossibleObstacle>& obstacles =
      edges ? inputs.edges->classification.possible_obstacles : kNone;
  // As the console: with the pair's own edge result, the NEP-corrected scan (NEP-corrected
  // points, confirmed outliers removed).
  // That scan is where edge processing had it (at the pair's time when it could be moved
  // there): drawn as it is, not moved a second time.
  const LaserScan* scan = inputs.scan ? &*inputs.scan : nullptr;
  const vision::ScanPlacement* placed = nullptr;
  if (edges && !inputs.edges->classification.corrected_scan.ranges_m.empty()) {
    scan = &inputs.edges->classification.corrected_scan;
    placed = &inputs.edges->placement;
  }
  std::string error;
  const fusion::ArFeatureBuilder& builder = builders_.For(
      ui::OverlayArOptions(options_.ar, options_.calibration.laser_height_m, false), &error);
  fusion::ArFeatures features;
  ComposedFrame frame;
  if (scan && placed) {
    frame.motion =
        ui::BuildPlacedOverlayFeatures(builder, *scan, *placed, pair.left.stamp,
                                       options_.motion.enabled, options_.motion, &features);
  } else if (scan) {
    fusion::MovedScan moved;
    const bool move = options_.motion.enabled && inputs.move_to_pair_time != nullptr;
    if (move) inputs.move_to_pair_time(*scan, &moved);
    frame.motion = ui::BuildOverlayFeatures(builder, *scan, move ? &moved : nullptr,
                                            options_.motion, &features);
  }
  render::OverlayGeometry geometry;
  ui::AssembleOverlay(nullptr, scan ? &features : nullptr, obstacles, fusion::VertexArray(),
                      &geometry);
  const math::CameraModel& model = geometry_.eye(0).image;
  const ImageOverlay overlay = ProjectOverlay(geometry, features.labels, model);
  const std::vector<MapPoint> map = MapPoints(features);

  // The sonar sectors as the console builds them, compared with this frame's laser points; in
  // a layer of their own so that the page draws them under the walls.
  fusion::SonarFeatures sonar;
  const bool with_sonar = inputs.sonar && options_.sonar.enabled;
  if (with_sonar) {
    fusion::ArFeatureOptions colors = options_.ar;
    colors.laser_height_m = static_cast<float>(options_.calibration.laser_height_m);
    fusion::LaserFieldOfView fov;  // none without a scan: nothing compared
    if (scan) fov = {scan->angle_min_rad, scan->angle_max_rad()};
    fusion::BuildSonarFeatures(*inputs.sonar, features.points, fov, colors, options_.sonar, &sonar);
  }
  render::OverlayGeometry sonar_geometry;
  ui::AssembleOverlay(&sonar, nullptr, kNone, fusion::VertexArray(), &sonar_geometry);
  const ImageOverlay sonar_overlay = ProjectOverlay(sonar_geometry, {}, model);
  const std::vector<MapPoint> sonar_map_triangles = MapVertices(sonar.fans);
  const std::vector<MapPoint> sonar_map_lines = MapVertices(sonar.outlines);

  FrameContent content;
  content.sequence = sequence;
  content.width_px = model.width_px();
  content.height_px = model.height_px();
  content.stamp = pair.left.stamp;
  if (scan) content.scan_stamp = scan->stamp;
  content.overlay = &overlay;
  content.map = &map;
  content.sonar = &sonar_overlay;
  content.sonar_map_triangles = &sonar_map_triangles;
  content.sonar_map_lines = &sonar_map_lines;
  content.sonar_echoes = static_cast<int>(std::min<size_t>(sonar.echoes, 65535));
  content.sonar_unseen =
      static_cast<int>(std::min<size_t>(sonar.unseen, static_cast<size_t>(content.sonar_echoes)));
  content.possible_obstacles = obstacles.size();
  content.flags = (edges ? kFrameEdges : 0u) | (with_sonar ? kFrameSonar : 0u);
  content.left_jpeg = &pair.left.data;
  frame.left_only = std::make_shared<const std::string>(EncodeFrame(content));
  if (both_eyes) {
    content.right_jpeg = &pair.right.data;
    frame.both_eyes = std::make_shared<const std::string>(EncodeFrame(content));
  }
  frame.triangles = overlay.triangles.size() / 3;
  frame.unprojectable = overlay.unprojectable + sonar_overlay.unprojectable;
  frame.sonar_triangles = sonar_overlay.triangles.size() / 3;
  frame.possible_obstacles = obstacles.size();
  frame.edges = edges;
  return frame;
}

}  // namespace mostar::web
