#include "operator_client/web/frame_composer.h"

#include "common/check/check.h"
#include "operator_client/render/overlay_geometry.h"
#include "operator_client/ui/overlay_assembly.h"
#include "operator_client/web/web_messages.h"

namespace mostar::web {

bool ComposerOptions::IsValid(std::string* error) const {
  if (!calibration.IsValid(error)) return false;
  if (!ar.IsValid(error)) return false;
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
}

void FrameComposer::SetRobotIntrinsics(const std::optional<CameraIntrinsicsInfo>& left,
                                       std::string* message) {
  message->clear();
  if (!options_.intrinsics_from_robot) return;
  const ui::IntrinsicsAdopter::Result result = intrinsics_.Apply(left, &options_.calibration);
  if (result.outcome == ui::IntrinsicsAdopter::Outcome::kRefused) *message = result.message;
  if (result.outcome == ui::IntrinsicsAdopter::Outcome::kAdopted) RefreshGeometry();
}

ComposedFrame FrameComposer::Compose(const CompressedStereoPair& pair,
                                     const std::optional<LaserScan>& scan,
                                     const std::vector<vision::PossibleObstacle>& obstacles,
                                     uint32_t sequence, bool both_eyes) {
  std::string error;
  const fusion::ArFeatureBuilder& builder = builders_.For(
      ui::OverlayArOptions(options_.ar, options_.calibration.laser_height_m, false), &error);
  fusion::ArFeatures features;
  if (scan) builder.Build(*scan, &features);
  render::OverlayGeometry geometry;
  ui::AssembleOverlay(nullptr, scan ? &features : nullptr, obstacles, fusion::VertexArray(),
                      &geometry);
  const math::CameraModel& model = geometry_.eye(0).image;
  const ImageOverlay overlay = ProjectOverlay(geometry, features.labels, model);
  const std::vector<MapPoint> map = MapPoints(features);

  FrameContent content;
  content.sequence = sequence;
  content.width_px = model.width_px();
  content.height_px = model.height_px();
  content.stamp = pair.left.stamp;
  if (scan) content.scan_stamp = scan->stamp;
  content.overlay = &overlay;
  content.map = &map;
  content.left_jpeg = &pair.left.data;
  ComposedFrame out;
  out.left_only = std::make_shared<const std::string>(EncodeFrame(content));
  if (both_eyes) {
    content.right_jpeg = &pair.right.data;
    out.both_eyes = std::make_shared<const std::string>(EncodeFrame(content));
  }
  out.triangles = overlay.triangles.size() / 3;
  out.unprojectable = overlay.unprojectable;
  return out;
}

}  // namespace mostar::web
